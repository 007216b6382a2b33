//! [`PluginModule`]: an actuation module whose code lives in a plugin library. It keeps
//! the parameters and logged data on proleg's side (checked and shown like any module's)
//! and calls the library's table each step with plain pointers, nothing allocated.
//!
//! A status other than OK (the plugin panicked) or a non-finite angle disables the
//! module: it records the cause ([`ActuationModule::failure`]), outputs 0 from then on
//! and never calls the library again for that instance.

use std::ffi::c_void;
use std::sync::Arc;

use proleg_plugin_api::{RawContext, STATUS_OK, STATUS_UNSUPPORTED};

use crate::config::module_types::ModuleDescriptor;
use crate::control::module::{ActuationModule, ModuleCore, StepContext};
use crate::plugin_host::library::PluginLibrary;
use crate::rng::SimRng;

/// One instance of a plugin module.
pub struct PluginModule {
    core: ModuleCore,
    library: Arc<PluginLibrary>,
    /// The library's instance; null once failed at creation or cloning.
    instance: *mut c_void,
    failure: Option<String>,
}

// SAFETY: the instance is the plugin's `Module`, which the API requires to be
// `Send + Sync`; proleg mutates it only through `&mut self`.
unsafe impl Send for PluginModule {}
unsafe impl Sync for PluginModule {}

impl PluginModule {
    /// A new instance for `joints` joints (failed, with the cause, if creation panicked).
    pub fn new(library: Arc<PluginLibrary>, descriptor: ModuleDescriptor, joints: usize) -> Self {
        // SAFETY: the table's `create` takes any joint count.
        let instance = unsafe { (library.table.create)(joints) };
        let mut m = PluginModule {
            core: ModuleCore::new(descriptor, joints),
            library,
            instance,
            failure: None,
        };
        if instance.is_null() {
            m.fail();
        }
        m
    }

    /// Records the library's last error and disables the module.
    fn fail(&mut self) {
        let cause = self.library.last_error();
        self.disable(cause);
    }

    fn disable(&mut self, cause: String) {
        self.failure = Some(format!(
            "plugin module {} ({}) {cause}; the module is disabled and outputs 0",
            self.core.descriptor.type_name,
            self.library.file.display()
        ));
    }

    fn usable(&self) -> bool {
        self.failure.is_none() && !self.instance.is_null()
    }
}

impl Drop for PluginModule {
    fn drop(&mut self) {
        if !self.instance.is_null() {
            // SAFETY: created by this library's `create`/`clone`, destroyed once.
            unsafe { (self.library.table.destroy)(self.instance) };
        }
    }
}

impl ActuationModule for PluginModule {
    fn core(&self) -> &ModuleCore {
        &self.core
    }

    fn core_mut(&mut self) -> &mut ModuleCore {
        &mut self.core
    }

    fn reset(&mut self, rng: &mut SimRng) {
        let seed = rng.next_u64();
        if self.usable() {
            // SAFETY: a live instance of this library.
            if unsafe { (self.library.table.reset)(self.instance, seed) } != STATUS_OK {
                self.fail();
            }
        }
    }

    fn compute(&mut self, ctx: &StepContext, out: &mut [f64]) {
        if !self.usable() {
            out.fill(0.0);
            return;
        }
        let ModuleCore { params, data, .. } = &mut self.core;
        let raw = RawContext {
            time: ctx.time,
            dt: ctx.dt,
            step: ctx.step,
            joints: ctx.angles.len(),
            angles: ctx.angles.as_ptr(),
            tactile: ctx.sensors.tactile.as_ptr(),
            tactile_count: ctx.sensors.tactile.len(),
            position: ctx.sensors.position,
        };
        // SAFETY: a live instance; `params` has parameters × joints values, `out` joints,
        // `data` series × joints, as the API lays them out; all valid for the call.
        let status = unsafe {
            (self.library.table.compute)(
                self.instance,
                &raw,
                params.values().as_ptr(),
                out.as_mut_ptr(),
                data.values_mut().as_mut_ptr(),
            )
        };
        if status != STATUS_OK {
            self.fail();
            out.fill(0.0);
        } else if let Some(j) = out.iter().position(|a| !a.is_finite()) {
            let cause = format!(
                "gave the angle {} for joint {j} at t = {} s",
                out[j], ctx.time
            );
            self.disable(cause);
            out.fill(0.0);
        }
    }

    fn clone_box(&self) -> Box<dyn ActuationModule> {
        let instance = if self.usable() {
            // SAFETY: a live instance of this library.
            unsafe { (self.library.table.clone)(self.instance) }
        } else {
            std::ptr::null_mut()
        };
        let mut copy = PluginModule {
            core: self.core.clone(),
            library: self.library.clone(),
            instance,
            failure: self.failure.clone(),
        };
        if instance.is_null() && copy.failure.is_none() {
            copy.fail();
        }
        Box::new(copy)
    }

    fn perturb(&mut self, joint: usize, amount: f64) -> bool {
        if !self.usable() || joint >= self.core.params.joints() {
            return false;
        }
        // SAFETY: a live instance of this library.
        match unsafe { (self.library.table.perturb)(self.instance, joint, amount) } {
            STATUS_OK => true,
            STATUS_UNSUPPORTED => false,
            _ => {
                self.fail();
                false
            }
        }
    }

    fn failure(&self) -> Option<&str> {
        self.failure.as_deref()
    }
}
