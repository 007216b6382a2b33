//! Finding and loading MuJoCo's shared library (once per process: the operating system
//! maps a library once anyway), checking its version against the headers the bindings
//! came from, and installing MuJoCo's error and warning hooks. MuJoCo's default error
//! handler ends the process; ours records the message for the engine to return as an
//! error, and MuJoCo carries on from its call.

use std::cell::RefCell;
use std::ffi::{CStr, c_char};
use std::path::PathBuf;
use std::sync::OnceLock;

use super::ffi::{MujocoApi, mjVERSION_HEADER};
use super::{MUJOCO_VERSION, MujocoError};

/// The environment variable naming the library (a file, or a folder holding
/// `lib/libmujoco.so.4.0.0` or `libmujoco.so.4.0.0`).
pub const LIBRARY_VARIABLE: &str = "PROLEG_MUJOCO";

/// The library's file name.
pub fn library_file_name() -> String {
    format!("libmujoco.so.{MUJOCO_VERSION}")
}

/// Where proleg looks for the library: `PROLEG_MUJOCO`, else the install folder.
pub fn library_path() -> PathBuf {
    let name = library_file_name();
    if let Some(v) = std::env::var_os(LIBRARY_VARIABLE).filter(|v| !v.is_empty()) {
        let p = PathBuf::from(v);
        if p.is_dir() {
            let nested = p.join("lib").join(&name);
            return if nested.exists() {
                nested
            } else {
                p.join(name)
            };
        }
        return p;
    }
    let home = std::env::var_os("HOME").map_or_else(|| PathBuf::from("."), PathBuf::from);
    home.join(".local/share/proleg/mujoco/lib").join(name)
}

thread_local! {
    /// The last error MuJoCo raised on this thread, taken by [`take_error`].
    static LAST_ERROR: RefCell<Option<String>> = const { RefCell::new(None) };
    /// The last warning MuJoCo gave on this thread, taken by [`take_warning`].
    static LAST_WARNING: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// The text of a message MuJoCo passes to a hook.
///
/// # Safety
/// `msg` is null or a NUL-terminated string that lives for the call.
unsafe fn message(msg: *const c_char) -> String {
    if msg.is_null() {
        String::from("unknown error")
    } else {
        // SAFETY: guaranteed by the caller.
        unsafe { CStr::from_ptr(msg) }
            .to_string_lossy()
            .trim()
            .to_string()
    }
}

/// MuJoCo's error hook: records the message instead of ending the process.
unsafe extern "C" fn on_error(msg: *const c_char) {
    // SAFETY: MuJoCo passes a NUL-terminated message that lives for the call.
    let text = unsafe { message(msg) };
    LAST_ERROR.with(|e| *e.borrow_mut() = Some(text));
}

/// MuJoCo's warning hook: a warning (e.g. an unstable simulation it reset, also counted in
/// `mjData::warning`) is kept for [`take_warning`], not printed.
unsafe extern "C" fn on_warning(msg: *const c_char) {
    // SAFETY: as for `on_error`.
    let text = unsafe { message(msg) };
    LAST_WARNING.with(|w| *w.borrow_mut() = Some(text));
}

/// The error MuJoCo raised on this thread since the last call, if any.
pub fn take_error() -> Option<String> {
    LAST_ERROR.with(|e| e.borrow_mut().take())
}

/// The warning MuJoCo gave on this thread since the last call, if any.
pub fn take_warning() -> Option<String> {
    LAST_WARNING.with(|w| w.borrow_mut().take())
}

/// The loaded library.
pub struct Library {
    /// Its functions.
    pub api: MujocoApi,
    /// Where it was loaded from.
    pub path: PathBuf,
}

static LOADED: OnceLock<Result<Library, MujocoError>> = OnceLock::new();

/// The library, loaded on first use from [`library_path`].
pub fn library() -> Result<&'static Library, MujocoError> {
    LOADED
        .get_or_init(|| load(library_path()))
        .as_ref()
        .map_err(Clone::clone)
}

/// Whether the library can be loaded (tests of the MuJoCo engine skip without it).
pub fn available() -> bool {
    library().is_ok()
}

type Hook = Option<unsafe extern "C" fn(*const c_char)>;

fn load(path: PathBuf) -> Result<Library, MujocoError> {
    let shown = path.display().to_string();
    if !path.exists() {
        return Err(MujocoError::Missing { path: shown });
    }
    let not_mujoco = |e: libloading::Error| MujocoError::NotMujoco {
        path: shown.clone(),
        cause: e.to_string(),
    };
    // SAFETY: loading runs the library's initialisers; MuJoCo's only set up its globals.
    let lib = unsafe { libloading::Library::new(&path) }.map_err(not_mujoco)?;
    // The version first, so that another MuJoCo says so rather than missing a symbol.
    // SAFETY: `mj_version` is `int mj_version(void)` in every MuJoCo.
    let version = unsafe {
        let f = lib
            .get::<unsafe extern "C" fn() -> std::ffi::c_int>(b"mj_version\0")
            .map_err(not_mujoco)?;
        f()
    };
    if version as u32 != mjVERSION_HEADER {
        return Err(MujocoError::WrongVersion {
            path: shown,
            found: version_name(version),
        });
    }
    // SAFETY: both symbols are MuJoCo's `void (*)(const char*)` hook variables; writing a
    // function pointer of that type into them is what MuJoCo documents for them.
    unsafe {
        for (name, hook) in [
            (
                &b"mju_user_error\0"[..],
                on_error as unsafe extern "C" fn(*const c_char),
            ),
            (&b"mju_user_warning\0"[..], on_warning),
        ] {
            let var = lib.get::<*mut Hook>(name).map_err(not_mujoco)?;
            **var = Some(hook);
        }
    }
    // SAFETY: every function of the table is looked up by its C name and has the
    // signature of the 4.0.0 headers; a missing one fails here.
    let api = unsafe { MujocoApi::from_library(lib) }.map_err(not_mujoco)?;
    Ok(Library { api, path })
}

/// MuJoCo's version number (e.g. 4000000) as `4.0.0`; older ones (e.g. 330) as `3.3.0`.
fn version_name(v: i32) -> String {
    if v >= 1_000_000 {
        format!("{}.{}.{}", v / 1_000_000, v / 1000 % 1000, v % 1000)
    } else {
        format!("{}.{}.{}", v / 100, v / 10 % 10, v % 10)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn versions_read_as_people_write_them() {
        assert_eq!(version_name(4_000_000), "4.0.0");
        assert_eq!(version_name(4_001_002), "4.1.2");
        assert_eq!(version_name(330), "3.3.0");
    }

    #[test]
    fn a_missing_file_says_what_to_run() {
        let e = load(PathBuf::from("/nonexistent/libmujoco.so.4.0.0"));
        let Err(e) = e else {
            panic!("a missing file loaded");
        };
        assert!(matches!(e, MujocoError::Missing { .. }), "{e:?}");
    }

    #[test]
    fn another_mujoco_says_its_version() {
        // Debian's MuJoCo (scripts/test installs libmujoco2.2.2).
        let old = PathBuf::from("/usr/lib/x86_64-linux-gnu/libmujoco.so.2.2.2");
        if !old.exists() {
            assert!(
                std::env::var_os("PROLEG_REQUIRE_MUJOCO").is_none(),
                "scripts/test installs libmujoco2.2.2"
            );
            return;
        }
        let Err(e) = load(old) else {
            panic!("MuJoCo 2.2.2 loaded as 4.0.0");
        };
        assert_eq!(
            e.to_string().split(" is MuJoCo ").nth(1).map(|t| &t[..5]),
            Some("2.2.2"),
            "{e}"
        );
        assert!(matches!(e, MujocoError::WrongVersion { .. }), "{e:?}");
    }

    #[test]
    fn a_library_that_is_not_mujoco_is_refused() {
        // libc exists on every machine and has no MuJoCo symbols.
        let libc = [
            "/lib/x86_64-linux-gnu/libc.so.6",
            "/usr/lib/x86_64-linux-gnu/libc.so.6",
        ]
        .into_iter()
        .map(PathBuf::from)
        .find(|p| p.exists());
        let Some(libc) = libc else {
            return;
        };
        let Err(e) = load(libc) else {
            panic!("libc loaded as MuJoCo");
        };
        assert!(matches!(e, MujocoError::NotMujoco { .. }), "{e:?}");
    }
}
