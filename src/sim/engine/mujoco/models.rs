//! Compiled MuJoCo models shared by the worlds built from the same MJCF document: the
//! first world compiles it, the others (an optimizer's next evaluation, an environment's
//! next episode, the other environments of a vector) reuse it while any holds it. MuJoCo
//! only reads a model while it steps, senses or casts rays (`const mjModel*`), so worlds on
//! any threads share one; a world that must change its model (dragging a static body)
//! takes a copy of its own first ([`MujocoModel::copy`]). Sharing skips the compile on
//! every reset and keeps one model in the caches for many worlds.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock, Weak};

use super::ffi::mjModel;
use super::library::Library;

/// A compiled model, freed when its last world drops it.
pub struct MujocoModel {
    lib: &'static Library,
    ptr: *mut mjModel,
}

// SAFETY: the model is plain memory MuJoCo allocated; shared models are only read (MuJoCo
// takes them as `const`), and a world writes only into a model it holds alone.
unsafe impl Send for MujocoModel {}
// SAFETY: as above.
unsafe impl Sync for MujocoModel {}

impl Drop for MujocoModel {
    fn drop(&mut self) {
        // SAFETY: made by MuJoCo, freed once, here.
        unsafe { self.lib.api.mj_deleteModel(self.ptr) };
    }
}

impl MujocoModel {
    /// Takes ownership of `ptr`, a model MuJoCo compiled (not null).
    pub fn new(lib: &'static Library, ptr: *mut mjModel) -> MujocoModel {
        MujocoModel { lib, ptr }
    }

    /// The model for MuJoCo's calls.
    pub fn ptr(&self) -> *mut mjModel {
        self.ptr
    }

    /// A copy of this model of its own (`None` when MuJoCo could not allocate it).
    pub fn copy(&self) -> Option<MujocoModel> {
        // SAFETY: a valid model; MuJoCo allocates the copy.
        let ptr = unsafe { self.lib.api.mj_copyModel(std::ptr::null_mut(), self.ptr) };
        (!ptr.is_null()).then(|| MujocoModel::new(self.lib, ptr))
    }
}

/// The models alive, by their document.
fn models() -> &'static Mutex<HashMap<String, Weak<MujocoModel>>> {
    static MODELS: OnceLock<Mutex<HashMap<String, Weak<MujocoModel>>>> = OnceLock::new();
    MODELS.get_or_init(Mutex::default)
}

/// The model of the document `xml`: the one a live world holds, else `compile`'s (kept for
/// the next world while any holds it). Compiles run one at a time, so worlds built together
/// on several threads compile a document once.
pub fn shared<E>(
    xml: &str,
    compile: impl FnOnce() -> Result<MujocoModel, E>,
) -> Result<Arc<MujocoModel>, E> {
    // A panic elsewhere while the lock was held leaves the map whole (every change to it
    // is one insert or retain), so a poisoned lock is taken as it is.
    let mut map = models().lock().unwrap_or_else(|e| e.into_inner());
    if let Some(model) = map.get(xml).and_then(Weak::upgrade) {
        return Ok(model);
    }
    let model = Arc::new(compile()?);
    map.retain(|_, m| m.strong_count() > 0);
    map.insert(xml.to_string(), Arc::downgrade(&model));
    Ok(model)
}
