//! # proleg-plugin-api
//!
//! Write a proleg actuation module (thesis 5.2, listing A.1) as a shared library that
//! proleg loads at run time, without rebuilding proleg.
//!
//! Implement [`Module`] for a type and export it with [`export_module!`]; build the crate
//! as a `cdylib` (`proleg plugin build NAME` does that and puts the library where proleg
//! looks for it). The module then appears in proleg's registry under [`Module::NAME`] and
//! can be named in actuation files, chosen in the wizard and tuned like a standard module.
//!
//! ```ignore
//! use proleg_plugin_api::{export_module, Context, Data, Module, Param, Params};
//!
//! #[derive(Clone)]
//! struct Wave { theta: Vec<f64> }
//!
//! impl Module for Wave {
//!     const NAME: &'static str = "Wave";
//!     const PARAMETERS: &'static [Param] = &[Param::new("Amplitude", 30.0, 0.0, 90.0).unit("deg")];
//!     const SERIES: &'static [&'static str] = &["Phase"];
//!     fn new(joints: usize) -> Self { Wave { theta: vec![0.0; joints] } }
//!     fn compute(&mut self, ctx: &Context, p: &Params, out: &mut [f64], data: &mut Data) { /* ... */ }
//! }
//! export_module!(Wave);
//! ```
//!
//! ## The boundary
//! Nothing Rust-specific crosses it: the library exports two `extern "C"` symbols,
//! [`VERSION_SYMBOL`] (returns [`ABI_VERSION`]; proleg refuses any other value before it
//! reads anything else) and [`TABLE_SYMBOL`] (returns a [`PluginTable`] of C function
//! pointers over an opaque instance pointer, `#[repr(C)]` descriptors and plain numbers).
//! Every entry catches panics: a panicking module reports a status instead of unwinding
//! into proleg, which then disables that module and shows the message (keep the default
//! `panic = "unwind"` in the plugin's profile).
//!
//! Parameter values belong to proleg, which checks them against the declared ranges
//! before any change and hands the current values to every step ([`Params`]); the
//! module writes its logged series into [`Data`].

use std::cell::RefCell;
use std::ffi::c_void;
use std::panic::{AssertUnwindSafe, catch_unwind};

/// The version of the table layout below; proleg loads only libraries that report it.
pub const ABI_VERSION: u32 = 1;
/// `extern "C" fn() -> u32`: the library's [`ABI_VERSION`].
pub const VERSION_SYMBOL: &[u8] = b"proleg_plugin_abi_version\0";
/// `extern "C" fn() -> *const PluginTable`.
pub const TABLE_SYMBOL: &[u8] = b"proleg_plugin_table\0";

/// Status: the call succeeded.
pub const STATUS_OK: i32 = 0;
/// Status: the module panicked; [`PluginTable::last_error`] has the message.
pub const STATUS_PANICKED: i32 = 1;
/// Status of `perturb`: the module has no state to disturb.
pub const STATUS_UNSUPPORTED: i32 = 2;

/// One parameter: name, initial value, range, unit and a help line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Param {
    pub name: &'static str,
    pub default: f64,
    pub min: f64,
    pub max: f64,
    pub unit: &'static str,
    pub help: &'static str,
}

impl Param {
    /// A parameter with this initial value and range, no unit, no help.
    pub const fn new(name: &'static str, default: f64, min: f64, max: f64) -> Self {
        Param {
            name,
            default,
            min,
            max,
            unit: "",
            help: "",
        }
    }

    /// The same parameter with a unit (shown in the GUI and messages).
    pub const fn unit(self, unit: &'static str) -> Self {
        Param { unit, ..self }
    }

    /// The same parameter with a help line.
    pub const fn help(self, help: &'static str) -> Self {
        Param { help, ..self }
    }
}

/// What the module sees in one step.
#[derive(Debug, Clone, Copy)]
pub struct Context<'a> {
    /// Simulated time (s) of the step being computed.
    pub time: f64,
    /// Step width (s).
    pub dt: f64,
    /// Step counter.
    pub step: u64,
    /// Measured angles (degrees) of the module's joints, in its joint order.
    pub angles: &'a [f64],
    /// Touch state of each tactile pad of the robot.
    pub tactile: &'a [bool],
    /// The robot's centre of mass in world coordinates (m).
    pub position: [f64; 3],
}

/// The current parameter values, one per parameter and joint.
#[derive(Debug, Clone, Copy)]
pub struct Params<'a> {
    values: &'a [f64],
    joints: usize,
}

impl<'a> Params<'a> {
    /// Values laid out row by row: `values[param * joints + joint]`.
    pub fn new(values: &'a [f64], joints: usize) -> Self {
        Params { values, joints }
    }

    /// Parameter `param` (index into [`Module::PARAMETERS`]) at `joint`.
    #[inline]
    pub fn get(&self, param: usize, joint: usize) -> f64 {
        self.values[param * self.joints + joint]
    }

    /// Every joint's value of parameter `param`.
    pub fn row(&self, param: usize) -> &'a [f64] {
        &self.values[param * self.joints..(param + 1) * self.joints]
    }
}

/// The logged series, one value per series and joint (the latest step's).
#[derive(Debug)]
pub struct Data<'a> {
    values: &'a mut [f64],
    joints: usize,
}

impl<'a> Data<'a> {
    /// Values laid out row by row: `values[series * joints + joint]`.
    pub fn new(values: &'a mut [f64], joints: usize) -> Self {
        Data { values, joints }
    }

    /// Sets series `series` (index into [`Module::SERIES`]) at `joint`.
    #[inline]
    pub fn set(&mut self, series: usize, joint: usize, value: f64) {
        self.values[series * self.joints + joint] = value;
    }

    /// Every joint's value of series `series`.
    pub fn series_mut(&mut self, series: usize) -> &mut [f64] {
        &mut self.values[series * self.joints..(series + 1) * self.joints]
    }
}

/// An actuation module: drives a group of joints, one angle (degrees) per joint per step.
pub trait Module: Clone + Send + Sync + 'static {
    /// The registry name (as written in actuation files).
    const NAME: &'static str;
    /// One line for lists and the GUI.
    const SUMMARY: &'static str = "";
    /// The parameters, per joint, with initial values and ranges.
    const PARAMETERS: &'static [Param];
    /// Names of the internal data series logged per joint.
    const SERIES: &'static [&'static str] = &[];
    /// Whether the module reads sensors.
    const SENSING: bool = false;

    /// A module for `joints` connected joints, in its start state.
    fn new(joints: usize) -> Self;
    /// Back to the start state before a run; `seed` seeds any randomness of the module.
    fn reset(&mut self, _seed: u64) {}
    /// One angle (degrees) per joint into `out`; logged values into `data`.
    fn compute(&mut self, ctx: &Context, params: &Params, out: &mut [f64], data: &mut Data);
    /// A one-off disturbance of joint `joint`'s state by `amount`; false without state.
    fn perturb(&mut self, _joint: usize, _amount: f64) -> bool {
        false
    }
}

/// A string as pointer and length (UTF-8, not NUL-terminated, static in the library).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct RawStr {
    pub ptr: *const u8,
    pub len: usize,
}

impl RawStr {
    pub const fn new(s: &'static str) -> Self {
        RawStr {
            ptr: s.as_ptr(),
            len: s.len(),
        }
    }
}

/// [`Param`] across the boundary.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct RawParam {
    pub name: RawStr,
    pub unit: RawStr,
    pub help: RawStr,
    pub default: f64,
    pub min: f64,
    pub max: f64,
}

/// The module type's description across the boundary.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct RawDescriptor {
    pub name: RawStr,
    pub summary: RawStr,
    pub params: *const RawParam,
    pub param_count: usize,
    pub series: *const RawStr,
    pub series_count: usize,
    pub sensing: bool,
}

/// [`Context`] across the boundary.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct RawContext {
    pub time: f64,
    pub dt: f64,
    pub step: u64,
    pub joints: usize,
    pub angles: *const f64,
    pub tactile: *const bool,
    pub tactile_count: usize,
    pub position: [f64; 3],
}

/// The exported function table (layout [`ABI_VERSION`]).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct PluginTable {
    pub abi_version: u32,
    pub descriptor: *const RawDescriptor,
    /// A new instance for `joints` joints; null when the module panicked.
    pub create: unsafe extern "C" fn(joints: usize) -> *mut c_void,
    /// Start state again; a status.
    pub reset: unsafe extern "C" fn(instance: *mut c_void, seed: u64) -> i32,
    /// One step: `params` (param × joints values), `out` (joints), `data` (series × joints).
    pub compute: unsafe extern "C" fn(
        instance: *mut c_void,
        ctx: *const RawContext,
        params: *const f64,
        out: *mut f64,
        data: *mut f64,
    ) -> i32,
    /// Disturbs one joint's state; [`STATUS_UNSUPPORTED`] when there is none.
    pub perturb: unsafe extern "C" fn(instance: *mut c_void, joint: usize, amount: f64) -> i32,
    /// A copy in the same state; null when the module panicked.
    pub clone: unsafe extern "C" fn(instance: *const c_void) -> *mut c_void,
    /// Frees an instance.
    pub destroy: unsafe extern "C" fn(instance: *mut c_void),
    /// Copies the calling thread's last panic message into `buf`; returns its full length.
    pub last_error: unsafe extern "C" fn(buf: *mut u8, capacity: usize) -> usize,
}

/// One instance as the library keeps it: the module and its joint count.
struct Instance<M> {
    module: M,
    joints: usize,
}

thread_local! {
    static LAST_ERROR: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Runs `f`, turning a panic into `Err` and remembering its message for `last_error`.
fn guarded<T>(what: &str, f: impl FnOnce() -> T) -> Result<T, ()> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic without a message".to_string());
        LAST_ERROR.with(|e| *e.borrow_mut() = format!("panicked in {what}: {message}"));
    })
}

unsafe extern "C" fn create<M: Module>(joints: usize) -> *mut c_void {
    guarded("create", || {
        Box::into_raw(Box::new(Instance {
            module: M::new(joints),
            joints,
        })) as *mut c_void
    })
    .unwrap_or(std::ptr::null_mut())
}

unsafe extern "C" fn reset<M: Module>(instance: *mut c_void, seed: u64) -> i32 {
    // SAFETY: proleg passes only pointers this library's `create`/`clone` returned.
    let inst = unsafe { &mut *(instance as *mut Instance<M>) };
    match guarded("reset", || inst.module.reset(seed)) {
        Ok(()) => STATUS_OK,
        Err(()) => STATUS_PANICKED,
    }
}

unsafe extern "C" fn compute<M: Module>(
    instance: *mut c_void,
    ctx: *const RawContext,
    params: *const f64,
    out: *mut f64,
    data: *mut f64,
) -> i32 {
    // SAFETY: proleg passes an instance of this library, a context whose slices are valid
    // for the step, `params` with PARAMETERS × joints values, `out` with joints values and
    // `data` with SERIES × joints values (the layout `Params` and `Data` describe).
    let (inst, ctx) = unsafe { (&mut *(instance as *mut Instance<M>), &*ctx) };
    let n = inst.joints;
    let (context, params, out, mut data) = unsafe {
        (
            Context {
                time: ctx.time,
                dt: ctx.dt,
                step: ctx.step,
                angles: slice(ctx.angles, ctx.joints),
                tactile: slice(ctx.tactile, ctx.tactile_count),
                position: ctx.position,
            },
            Params::new(slice(params, M::PARAMETERS.len() * n), n),
            slice_mut(out, n),
            Data::new(slice_mut(data, M::SERIES.len() * n), n),
        )
    };
    match guarded("compute", || {
        inst.module.compute(&context, &params, out, &mut data)
    }) {
        Ok(()) => STATUS_OK,
        Err(()) => STATUS_PANICKED,
    }
}

/// A slice from a pointer that may be dangling when `len` is 0.
unsafe fn slice<'a, T>(ptr: *const T, len: usize) -> &'a [T] {
    if len == 0 || ptr.is_null() {
        &[]
    } else {
        // SAFETY: the caller guarantees `len` valid elements at `ptr`.
        unsafe { std::slice::from_raw_parts(ptr, len) }
    }
}

unsafe fn slice_mut<'a, T>(ptr: *mut T, len: usize) -> &'a mut [T] {
    if len == 0 || ptr.is_null() {
        &mut []
    } else {
        // SAFETY: the caller guarantees `len` valid, unaliased elements at `ptr`.
        unsafe { std::slice::from_raw_parts_mut(ptr, len) }
    }
}

unsafe extern "C" fn perturb<M: Module>(instance: *mut c_void, joint: usize, amount: f64) -> i32 {
    // SAFETY: an instance of this library.
    let inst = unsafe { &mut *(instance as *mut Instance<M>) };
    match guarded("perturb", || inst.module.perturb(joint, amount)) {
        Ok(true) => STATUS_OK,
        Ok(false) => STATUS_UNSUPPORTED,
        Err(()) => STATUS_PANICKED,
    }
}

unsafe extern "C" fn clone<M: Module>(instance: *const c_void) -> *mut c_void {
    // SAFETY: an instance of this library.
    let inst = unsafe { &*(instance as *const Instance<M>) };
    guarded("clone", || {
        Box::into_raw(Box::new(Instance {
            module: inst.module.clone(),
            joints: inst.joints,
        })) as *mut c_void
    })
    .unwrap_or(std::ptr::null_mut())
}

unsafe extern "C" fn destroy<M: Module>(instance: *mut c_void) {
    if !instance.is_null() {
        // SAFETY: an instance of this library, destroyed once.
        let boxed = unsafe { Box::from_raw(instance as *mut Instance<M>) };
        let _ = guarded("destroy", move || drop(boxed));
    }
}

unsafe extern "C" fn last_error(buf: *mut u8, capacity: usize) -> usize {
    LAST_ERROR.with(|e| {
        let e = e.borrow();
        let n = e.len().min(capacity);
        if n > 0 && !buf.is_null() {
            // SAFETY: the caller provides `capacity` writable bytes at `buf`.
            unsafe { std::ptr::copy_nonoverlapping(e.as_ptr(), buf, n) };
        }
        e.len()
    })
}

/// The table and the descriptor storage it points into, built once per library.
pub struct Exported {
    table: PluginTable,
    _descriptor: Box<RawDescriptor>,
    _params: Vec<RawParam>,
    _series: Vec<RawStr>,
}

// SAFETY: everything the raw pointers reach is immutable after construction and lives
// (in `Exported`, itself in a static) as long as the library.
unsafe impl Sync for Exported {}
unsafe impl Send for Exported {}

impl Exported {
    /// The table of module type `M`.
    pub fn new<M: Module>() -> Self {
        let params: Vec<RawParam> = M::PARAMETERS
            .iter()
            .map(|p| RawParam {
                name: RawStr::new(p.name),
                unit: RawStr::new(p.unit),
                help: RawStr::new(p.help),
                default: p.default,
                min: p.min,
                max: p.max,
            })
            .collect();
        let series: Vec<RawStr> = M::SERIES.iter().map(|s| RawStr::new(s)).collect();
        let descriptor = Box::new(RawDescriptor {
            name: RawStr::new(M::NAME),
            summary: RawStr::new(M::SUMMARY),
            params: params.as_ptr(),
            param_count: params.len(),
            series: series.as_ptr(),
            series_count: series.len(),
            sensing: M::SENSING,
        });
        let table = PluginTable {
            abi_version: ABI_VERSION,
            descriptor: &*descriptor,
            create: create::<M>,
            reset: reset::<M>,
            compute: compute::<M>,
            perturb: perturb::<M>,
            clone: clone::<M>,
            destroy: destroy::<M>,
            last_error,
        };
        Exported {
            table,
            _descriptor: descriptor,
            _params: params,
            _series: series,
        }
    }

    /// The table to hand to proleg.
    pub fn table(&self) -> *const PluginTable {
        &self.table
    }
}

/// Exports module type `$module` (implementing [`Module`]) from this `cdylib`.
#[macro_export]
macro_rules! export_module {
    ($module:ty) => {
        /// The plugin ABI version this library was built against.
        #[unsafe(no_mangle)]
        pub extern "C" fn proleg_plugin_abi_version() -> u32 {
            $crate::ABI_VERSION
        }

        /// The function table of the exported module.
        #[unsafe(no_mangle)]
        pub extern "C" fn proleg_plugin_table() -> *const $crate::PluginTable {
            static EXPORTED: ::std::sync::OnceLock<$crate::Exported> = ::std::sync::OnceLock::new();
            EXPORTED
                .get_or_init($crate::Exported::new::<$module>)
                .table()
        }
    };
}

/// Helpers for module code.
pub mod helpers {
    /// Wraps an angle in radians into [0, 2π).
    #[inline]
    pub fn wrap_tau(x: f64) -> f64 {
        x.rem_euclid(std::f64::consts::TAU)
    }

    /// A small seeded generator (splitmix64) for modules with randomness.
    #[derive(Debug, Clone)]
    pub struct Rng(u64);

    impl Rng {
        pub fn new(seed: u64) -> Self {
            Rng(seed)
        }

        pub fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }

        /// Uniform in [0, 1).
        pub fn uniform(&mut self) -> f64 {
            (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone)]
    struct Ramp;

    impl Module for Ramp {
        const NAME: &'static str = "Ramp";
        const PARAMETERS: &'static [Param] = &[Param::new("Slope", 1.0, 0.0, 10.0)];
        const SERIES: &'static [&'static str] = &["Time"];
        fn new(_joints: usize) -> Self {
            Ramp
        }
        fn compute(&mut self, ctx: &Context, p: &Params, out: &mut [f64], data: &mut Data) {
            if ctx.time > 1.0 {
                panic!("too late: {}", ctx.time);
            }
            for (j, o) in out.iter_mut().enumerate() {
                *o = p.get(0, j) * ctx.time;
                data.set(0, j, ctx.time);
            }
        }
    }

    fn step(table: &PluginTable, inst: *mut c_void, time: f64, params: &[f64]) -> (i32, Vec<f64>) {
        let ctx = RawContext {
            time,
            dt: 0.01,
            step: 0,
            joints: 2,
            angles: [0.0, 0.0].as_ptr(),
            tactile: std::ptr::null(),
            tactile_count: 0,
            position: [0.0; 3],
        };
        let mut out = vec![0.0; 2];
        let mut data = vec![0.0; 2];
        let status = unsafe {
            (table.compute)(
                inst,
                &ctx,
                params.as_ptr(),
                out.as_mut_ptr(),
                data.as_mut_ptr(),
            )
        };
        (status, out)
    }

    #[test]
    fn the_table_runs_the_module_and_catches_its_panic() {
        let exported = Exported::new::<Ramp>();
        let table = unsafe { &*exported.table() };
        assert_eq!(table.abi_version, ABI_VERSION);
        let d = unsafe { &*table.descriptor };
        assert_eq!((d.param_count, d.series_count), (1, 1));
        let inst = unsafe { (table.create)(2) };
        assert!(!inst.is_null());
        assert_eq!(
            step(table, inst, 0.5, &[2.0, 4.0]),
            (STATUS_OK, vec![1.0, 2.0])
        );
        let copy = unsafe { (table.clone)(inst) };
        assert_eq!(step(table, copy, 2.0, &[1.0, 1.0]).0, STATUS_PANICKED);
        let mut buf = [0u8; 128];
        let n = unsafe { (table.last_error)(buf.as_mut_ptr(), buf.len()) };
        let message = std::str::from_utf8(&buf[..n]).unwrap();
        assert_eq!(message, "panicked in compute: too late: 2");
        assert_eq!(unsafe { (table.perturb)(inst, 0, 1.0) }, STATUS_UNSUPPORTED);
        unsafe {
            (table.destroy)(inst);
            (table.destroy)(copy);
        }
    }
}
