//! The FMI 2.0 C ABI (`fmi2Functions.h`, co-simulation): each function checks its pointers,
//! hands the work to [`Instance`], logs a refusal through the host's logger and returns
//! `fmi2Error`; a panic is caught at the boundary and reported the same way, never unwound
//! into the host. The model-exchange functions are exported too, refusing (the description
//! declares co-simulation only), so that importers that load every symbol find them.

use hdgear::physical::fmu::{FmuError, Instance, Resources};
use std::ffi::{CStr, CString, c_char, c_int, c_uint, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// `fmi2Component` and `fmi2FMUstate`: opaque pointers.
pub type Component = *mut c_void;
/// `fmi2Status`.
pub type Status = c_int;
/// `fmi2ValueReference`.
pub type ValueReference = c_uint;
/// `fmi2Boolean`.
pub type Boolean = c_int;

const OK: Status = 0;
const DISCARD: Status = 2;
const ERROR: Status = 3;
const CO_SIMULATION: c_int = 1;
const LAST_SUCCESSFUL_TIME: c_int = 2;
const TERMINATED: c_int = 3;

/// `fmi2CallbackLogger`: (environment, instance name, status, category, format, ...).
pub type Logger = Option<
    unsafe extern "C" fn(*mut c_void, *const c_char, Status, *const c_char, *const c_char, ...),
>;

/// `fmi2CallbackFunctions`.
#[repr(C)]
pub struct CallbackFunctions {
    /// The host's logger.
    pub logger: Logger,
    /// The host's allocator (not used: the description says so).
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// The host's deallocator (not used).
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// For asynchronous steps (not used: steps are synchronous).
    pub step_finished: Option<unsafe extern "C" fn(*mut c_void, Status)>,
    /// Passed back to the logger.
    pub component_environment: *mut c_void,
}

/// One instance as the host holds it.
struct Slave {
    fmu: Instance,
    name: CString,
    logger: Logger,
    env: *mut c_void,
    logging: bool,
}

/// Calls the host's logger with `message` (through `%s`, so no `%` in it is read as a format).
fn log(
    logger: Logger,
    env: *mut c_void,
    name: &CStr,
    status: Status,
    category: &str,
    message: &str,
) {
    let Some(logger) = logger else { return };
    let category = CString::new(category).unwrap_or_default();
    let message = CString::new(message.replace('\0', " ")).unwrap_or_default();
    // SAFETY: the host gave this logger with this environment at fmi2Instantiate; every
    // pointer passed is a live NUL-terminated string, and the format "%s" reads exactly the
    // one string argument given.
    unsafe {
        logger(
            env,
            name.as_ptr(),
            status,
            category.as_ptr(),
            c"%s".as_ptr(),
            message.as_ptr(),
        );
    }
}

impl Slave {
    fn log(&self, status: Status, category: &str, message: &str) {
        log(self.logger, self.env, &self.name, status, category, message);
    }

    /// `fmi2OK`, or the refusal logged and `fmi2Error`.
    fn status(&self, r: Result<(), FmuError>) -> Status {
        match r {
            Ok(()) => OK,
            Err(e) => {
                self.log(ERROR, "logStatusError", &e.to_string());
                ERROR
            }
        }
    }
}

/// Runs `f` on the instance behind `c`: `fmi2Error` for a null pointer, and a panic caught,
/// logged and turned into `fmi2Error`.
fn with(c: Component, call: &str, f: impl FnOnce(&mut Slave) -> Status) -> Status {
    if c.is_null() {
        return ERROR;
    }
    let slave = c.cast::<Slave>();
    // SAFETY: a non-null component is one fmi2Instantiate returned and fmi2FreeInstance has not
    // freed (FMI: the host passes back only those), and the host calls an instance from one
    // thread at a time, so this is the only reference to it during the call.
    let r = catch_unwind(AssertUnwindSafe(|| f(unsafe { &mut *slave })));
    r.unwrap_or_else(|_| {
        // SAFETY: as above; the closure's borrow ended with the panic.
        let s = unsafe { &*slave };
        s.log(ERROR, "logStatusError", &format!("{call}: internal error"));
        ERROR
    })
}

/// The string behind `p`, if it is not null and is UTF-8.
///
/// # Safety
/// `p` is null or points to a NUL-terminated string that lives through the call.
unsafe fn text<'a>(p: *const c_char) -> Option<&'a str> {
    if p.is_null() {
        return None;
    }
    // SAFETY: the caller's contract.
    unsafe { CStr::from_ptr(p) }.to_str().ok()
}

/// The slices the host passes as (pointer, length): empty for a zero length, whatever the
/// pointer.
///
/// # Safety
/// With `n > 0`, `p` points to `n` valid values that live through the call.
unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        return Some(&[]);
    }
    if p.is_null() {
        return None;
    }
    // SAFETY: the caller's contract.
    Some(unsafe { std::slice::from_raw_parts(p, n) })
}

/// `fmi2GetTypesPlatform`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

/// `fmi2GetVersion`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// `fmi2SetDebugLogging`: on or off for every category.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetDebugLogging(
    c: Component,
    on: Boolean,
    _n: usize,
    _categories: *const *const c_char,
) -> Status {
    with(c, "fmi2SetDebugLogging", |s| {
        s.logging = on != 0;
        OK
    })
}

/// `fmi2Instantiate`: the drive from the FMU's resources, checked against the GUID; null (with
/// the reason logged) for model exchange, a wrong GUID or unreadable resources.
///
/// # Safety
/// The strings are null or NUL-terminated; `functions` is null or points to the host's
/// callbacks, which live as long as the instance (FMI 2.0, 2.1.5).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    name: *const c_char,
    kind: c_int,
    guid: *const c_char,
    resources: *const c_char,
    functions: *const CallbackFunctions,
    _visible: Boolean,
    logging: Boolean,
) -> Component {
    // SAFETY: the function's contract.
    let (logger, env) = match unsafe { functions.as_ref() } {
        Some(f) => (f.logger, f.component_environment),
        None => (None, std::ptr::null_mut()),
    };
    // SAFETY: the function's contract.
    let (name, guid, resources) = unsafe { (text(name), text(guid), text(resources)) };
    let label = CString::new(name.unwrap_or("hdgear")).unwrap_or_default();
    let refuse = |message: &str| {
        log(logger, env, &label, ERROR, "logStatusError", message);
        std::ptr::null_mut()
    };
    if kind != CO_SIMULATION {
        return refuse("this FMU is co-simulation only");
    }
    let (Some(guid), Some(resources)) = (guid, resources) else {
        return refuse("fmi2Instantiate needs the GUID and the resource location");
    };
    let loaded = catch_unwind(|| Resources::load(resources, guid));
    match loaded {
        Ok(Ok(r)) => Box::into_raw(Box::new(Slave {
            fmu: Instance::new(r.drive),
            name: label,
            logger,
            env,
            logging: logging != 0,
        }))
        .cast(),
        Ok(Err(e)) => refuse(&e.to_string()),
        Err(_) => refuse("fmi2Instantiate: internal error"),
    }
}

/// `fmi2FreeInstance`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2FreeInstance(c: Component) {
    if !c.is_null() {
        // SAFETY: a non-null component is one fmi2Instantiate made with Box::into_raw, freed
        // here once (FMI: the host frees each instance once and uses it no more).
        drop(unsafe { Box::from_raw(c.cast::<Slave>()) });
    }
}

/// `fmi2SetupExperiment`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetupExperiment(
    c: Component,
    tolerance_defined: Boolean,
    tolerance: f64,
    start: f64,
    _stop_defined: Boolean,
    _stop: f64,
) -> Status {
    with(c, "fmi2SetupExperiment", |s| {
        let tol = (tolerance_defined != 0).then_some(tolerance);
        let r = s.fmu.setup(tol, start);
        s.status(r)
    })
}

/// `fmi2EnterInitializationMode`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2EnterInitializationMode(c: Component) -> Status {
    with(c, "fmi2EnterInitializationMode", |s| {
        let r = s.fmu.enter_initialisation();
        s.status(r)
    })
}

/// `fmi2ExitInitializationMode`: the drive is built and checked here.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2ExitInitializationMode(c: Component) -> Status {
    with(c, "fmi2ExitInitializationMode", |s| {
        let r = s.fmu.exit_initialisation();
        if r.is_ok() && s.logging {
            s.log(OK, "logEvents", "initialised: the drive at rest");
        }
        s.status(r)
    })
}

/// `fmi2Terminate`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2Terminate(c: Component) -> Status {
    with(c, "fmi2Terminate", |s| {
        let r = s.fmu.terminate();
        s.status(r)
    })
}

/// `fmi2Reset`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2Reset(c: Component) -> Status {
    with(c, "fmi2Reset", |s| {
        s.fmu.reset();
        OK
    })
}

/// `fmi2GetReal`.
///
/// # Safety
/// `vr` and `value` point to `n` values each (FMI 2.0, 2.1.7).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *mut f64,
) -> Status {
    with(c, "fmi2GetReal", |s| {
        // SAFETY: the function's contract.
        let Some(refs) = (unsafe { slice(vr, n) }) else {
            return ERROR;
        };
        if n > 0 && value.is_null() {
            return ERROR;
        }
        for (i, &r) in refs.iter().enumerate() {
            match s.fmu.get_real(r) {
                // SAFETY: i < n, and `value` holds n values (the function's contract).
                Ok(v) => unsafe { *value.add(i) = v },
                Err(e) => return s.status(Err(e)),
            }
        }
        OK
    })
}

/// `fmi2SetReal`.
///
/// # Safety
/// `vr` and `value` point to `n` values each (FMI 2.0, 2.1.7).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: Component,
    vr: *const ValueReference,
    n: usize,
    value: *const f64,
) -> Status {
    with(c, "fmi2SetReal", |s| {
        // SAFETY: the function's contract.
        let (Some(refs), Some(values)) = (unsafe { slice(vr, n) }, unsafe { slice(value, n) })
        else {
            return ERROR;
        };
        for (&r, &v) in refs.iter().zip(values) {
            let done = s.fmu.set_real(r, v);
            if done.is_err() {
                return s.status(done);
            }
        }
        OK
    })
}

/// The Integer, Boolean and String accessors: the FMU has no such variable, so any reference
/// is refused (an empty request is fine).
macro_rules! no_variables {
    ($($name:ident($ty:ty, $what:literal);)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: the FMU has no ", $what, " variable.")]
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(c: Component, _vr: *const ValueReference, n: usize, _value: $ty) -> Status {
            with(c, stringify!($name), |s| {
                if n == 0 {
                    return OK;
                }
                s.log(ERROR, "logStatusError", concat!("this FMU has no ", $what, " variable"));
                ERROR
            })
        }
    )*};
}

no_variables! {
    fmi2GetInteger(*mut c_int, "Integer");
    fmi2SetInteger(*const c_int, "Integer");
    fmi2GetBoolean(*mut Boolean, "Boolean");
    fmi2SetBoolean(*const Boolean, "Boolean");
    fmi2GetString(*mut *const c_char, "String");
    fmi2SetString(*const *const c_char, "String");
}

/// `fmi2GetFMUstate`: a copy of the instance, drive state included.
///
/// # Safety
/// `state` is null or points to a state slot of the host's.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Component, state: *mut Component) -> Status {
    with(c, "fmi2GetFMUstate", |s| {
        if state.is_null() {
            return ERROR;
        }
        let copy = Box::into_raw(Box::new(s.fmu.clone())).cast();
        // SAFETY: `state` points to the host's slot (the function's contract). A state the slot
        // held already is one of ours: freed first (FMI 2.0, 2.1.8: it is overwritten).
        unsafe {
            let old = *state;
            if !old.is_null() {
                drop(Box::from_raw(old.cast::<Instance>()));
            }
            *state = copy;
        }
        OK
    })
}

/// `fmi2SetFMUstate`: the instance as it was when the state was taken.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2SetFMUstate(c: Component, state: Component) -> Status {
    with(c, "fmi2SetFMUstate", |s| {
        if state.is_null() {
            return ERROR;
        }
        // SAFETY: a non-null state is one fmi2GetFMUstate made and fmi2FreeFMUstate has not
        // freed (FMI: the host passes back only those).
        s.fmu = unsafe { &*state.cast::<Instance>() }.clone();
        OK
    })
}

/// `fmi2FreeFMUstate`.
///
/// # Safety
/// `state` is null or points to a slot holding null or a state fmi2GetFMUstate made.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: Component, state: *mut Component) -> Status {
    with(c, "fmi2FreeFMUstate", |_| {
        if state.is_null() {
            return OK;
        }
        // SAFETY: the function's contract; the slot is cleared so it is freed once.
        unsafe {
            let old = *state;
            if !old.is_null() {
                drop(Box::from_raw(old.cast::<Instance>()));
            }
            *state = std::ptr::null_mut();
        }
        OK
    })
}

/// What is declared unsupported in the description, refused with its reason when called.
macro_rules! unsupported {
    ($($name:ident($($arg:ident: $ty:ty),*) $why:literal;)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: ", $why, ".")]
        #[unsafe(no_mangle)]
        pub extern "C" fn $name(c: Component, $(_: $ty),*) -> Status {
            with(c, stringify!($name), |s| {
                s.log(ERROR, "logStatusError", concat!(stringify!($name), ": ", $why));
                ERROR
            })
        }
    )*};
}

unsupported! {
    fmi2SerializedFMUstateSize(state: Component, size: *mut usize)
        "not supported (canSerializeFMUstate is false)";
    fmi2SerializeFMUstate(state: Component, bytes: *mut c_char, size: usize)
        "not supported (canSerializeFMUstate is false)";
    fmi2DeSerializeFMUstate(bytes: *const c_char, size: usize, state: *mut Component)
        "not supported (canSerializeFMUstate is false)";
    fmi2GetDirectionalDerivative(unknown: *const ValueReference, nu: usize, known: *const ValueReference, nk: usize, dv_known: *const f64, dv_unknown: *mut f64)
        "not supported (providesDirectionalDerivative is false)";
    fmi2SetRealInputDerivatives(vr: *const ValueReference, n: usize, order: *const c_int, value: *const f64)
        "not supported (canInterpolateInputs is false: inputs are held over a step)";
    fmi2GetRealOutputDerivatives(vr: *const ValueReference, n: usize, order: *const c_int, value: *mut f64)
        "not supported (maxOutputDerivativeOrder is 0)";
    fmi2CancelStep()
        "not supported (steps are synchronous)";
    fmi2EnterEventMode()
        "model exchange is not supported (co-simulation only)";
    fmi2NewDiscreteStates(info: *mut c_void)
        "model exchange is not supported (co-simulation only)";
    fmi2EnterContinuousTimeMode()
        "model exchange is not supported (co-simulation only)";
    fmi2CompletedIntegratorStep(no_set: Boolean, enter: *mut Boolean, terminate: *mut Boolean)
        "model exchange is not supported (co-simulation only)";
    fmi2SetTime(t: f64)
        "model exchange is not supported (co-simulation only)";
    fmi2SetContinuousStates(x: *const f64, n: usize)
        "model exchange is not supported (co-simulation only)";
    fmi2GetDerivatives(dx: *mut f64, n: usize)
        "model exchange is not supported (co-simulation only)";
    fmi2GetEventIndicators(z: *mut f64, n: usize)
        "model exchange is not supported (co-simulation only)";
    fmi2GetContinuousStates(x: *mut f64, n: usize)
        "model exchange is not supported (co-simulation only)";
    fmi2GetNominalsOfContinuousStates(x: *mut f64, n: usize)
        "model exchange is not supported (co-simulation only)";
}

/// `fmi2DoStep`: hdgear's stepper from `current` over `h` seconds, the inputs held.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2DoStep(c: Component, current: f64, h: f64, _no_set_prior: Boolean) -> Status {
    with(c, "fmi2DoStep", |s| {
        let r = s.fmu.do_step(current, h);
        s.status(r)
    })
}

/// `fmi2GetStatus`: steps are synchronous, so there is never a pending one to ask about.
///
/// # Safety
/// `value` is null or points to a status slot of the host's.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(c: Component, _kind: c_int, value: *mut Status) -> Status {
    with(c, "fmi2GetStatus", |_| {
        if !value.is_null() {
            // SAFETY: the function's contract.
            unsafe { *value = OK };
        }
        DISCARD
    })
}

/// `fmi2GetRealStatus`: the last successful time.
///
/// # Safety
/// `value` is null or points to a real of the host's.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(c: Component, kind: c_int, value: *mut f64) -> Status {
    with(c, "fmi2GetRealStatus", |s| match s.fmu.time() {
        Some(t) if kind == LAST_SUCCESSFUL_TIME && !value.is_null() => {
            // SAFETY: the function's contract.
            unsafe { *value = t };
            OK
        }
        _ => DISCARD,
    })
}

/// `fmi2GetIntegerStatus`: no integer status.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetIntegerStatus(c: Component, _kind: c_int, _value: *mut c_int) -> Status {
    with(c, "fmi2GetIntegerStatus", |_| DISCARD)
}

/// `fmi2GetBooleanStatus`: the slave never asks to terminate.
///
/// # Safety
/// `value` is null or points to a boolean of the host's.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: Component,
    kind: c_int,
    value: *mut Boolean,
) -> Status {
    with(c, "fmi2GetBooleanStatus", |_| {
        if kind != TERMINATED || value.is_null() {
            return DISCARD;
        }
        // SAFETY: the function's contract.
        unsafe { *value = 0 };
        OK
    })
}

/// `fmi2GetStringStatus`: no string status.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetStringStatus(
    c: Component,
    _kind: c_int,
    _value: *mut *const c_char,
) -> Status {
    with(c, "fmi2GetStringStatus", |_| DISCARD)
}
