//! Every model envc parses or compiles goes through here: MuJoCo's parser and compiler called
//! from the C++ shim `csrc/mujoco_catch.cc`, so a C++ exception escaping them (MuJoCo catches
//! only its own errors; a `std::bad_alloc` when a model needs more memory than the process may
//! have) or an `mju_error` becomes an `Err` with a message, instead of ending the process
//! (mujoco-rs calls them `extern "C"`, where an exception aborts). docs/limits.md.

use mujoco_rs::mujoco_c::{mjModel, mjSpec};
use mujoco_rs::prelude::*;
use std::ffi::{CString, c_char, c_int};
use std::path::Path;

// `C`, not `C-unwind`: the shim lets nothing escape. (It runs MuJoCo with a thread log handler
// of its own, so envc's `mju_error` handler — a Rust panic — is never entered beneath it.)
unsafe extern "C" {
    fn envc_check_parse(path: *const c_char, error: *mut c_char, n: c_int) -> c_int;
    fn envc_compile(s: *mut mjSpec, into: *mut mjModel, error: *mut c_char, n: c_int) -> c_int;
    #[cfg(test)]
    fn envc_raise_mju_error(message: *const c_char, error: *mut c_char, n: c_int) -> c_int;
}

/// The shim's answer as a message: 1 MuJoCo's own refusal, 2 a C++ exception ("<type>: <what>"),
/// 3 an `mju_error`.
fn message(status: c_int, buf: &[c_char]) -> String {
    // SAFETY: the shim always NUL-terminates within the buffer (snprintf / MuJoCo's own copy).
    let text = unsafe { std::ffi::CStr::from_ptr(buf.as_ptr()) }
        .to_string_lossy()
        .trim()
        .to_string();
    match status {
        2 if text.starts_with("std::bad_alloc")
            || text.starts_with("std::bad_array_new_length") =>
        {
            format!(
                "MuJoCo threw {text}: the model needs more memory than is available to envc \
                 (the machine's memory or a limit such as `ulimit -v`); make the model smaller \
                 (its <size> numbers, textures, meshes, element counts) or allow more memory"
            )
        }
        2 => format!("MuJoCo threw a C++ exception, {text}"),
        _ => text,
    }
}

/// Parse a model file (MJCF or URDF) into an mjSpec; MuJoCo's message on failure.
pub(crate) fn parse(path: &Path) -> Result<MjSpec, String> {
    crate::mj::log::install();
    let s = path.to_str().ok_or("the path is not valid UTF-8")?;
    let c = CString::new(s).map_err(|_| "the path contains a NUL byte".to_string())?;
    let mut buf = [0 as c_char; 1024];
    // SAFETY: a NUL-terminated path and a writable buffer of the length given.
    let status = unsafe { envc_check_parse(c.as_ptr(), buf.as_mut_ptr(), buf.len() as c_int) };
    if status != 0 {
        return Err(message(status, &buf));
    }
    // mujoco-rs has no constructor from a raw mjSpec, so the file the shim has just parsed
    // without incident is parsed again by mujoco-rs (a few per cent of a compile; docs/limits.md).
    MjSpec::from_xml(path).map_err(|e| e.to_string())
}

/// Compile an mjSpec; MuJoCo's message on failure. The model is byte for byte what
/// `MjSpec::compile` makes (the shim moves mj_compile's result into a model mujoco-rs owns).
pub(crate) fn compile(spec: &mut MjSpec) -> Result<MjModel, String> {
    // `<compiler settotalmass>` is deprecated in MuJoCo: envc applies it (`total_mass`).
    let Some(taken) = crate::total_mass::take(spec) else {
        return compile_as_is(spec);
    };
    let compiled = compile_as_is(spec);
    crate::total_mass::restore(spec, &taken);
    let mut model = compiled?;
    crate::total_mass::apply(spec, &mut model, &taken)?;
    Ok(model)
}

/// [`compile`] of the spec exactly as it is.
fn compile_as_is(spec: &mut MjSpec) -> Result<MjModel, String> {
    crate::mj::log::install();
    // An empty model owned by mujoco-rs, whose contents the shim replaces.
    let mut model = MjSpec::new().compile().map_err(|e| e.to_string())?;
    let mut buf = [0 as c_char; 1024];
    // SAFETY: live spec and model pointers, used by nothing else during the call; the shim
    // replaces the model's contents only with a whole compiled model (and frees the old ones).
    let status = unsafe {
        envc_compile(
            spec.ffi_mut(),
            model.ffi_mut(),
            buf.as_mut_ptr(),
            buf.len() as c_int,
        )
    };
    if status != 0 {
        return Err(message(status, &buf));
    }
    Ok(model)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every bundled model (and the URDF fixtures) compiled through the shim is byte for byte
    /// the model mujoco-rs's own `mj_loadXML` makes: its mjb file and its whole buffer.
    #[test]
    fn shim_models_are_mujoco_rs_models_byte_for_byte() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let mut files = vec![];
        let mut dirs = vec![root.join("assets"), root.join("tests/fixtures/urdf")];
        while let Some(d) = dirs.pop() {
            for e in std::fs::read_dir(&d).unwrap() {
                let p = e.unwrap().path();
                if p.is_dir() {
                    dirs.push(p);
                } else if matches!(p.extension().and_then(|x| x.to_str()), Some("xml" | "urdf")) {
                    files.push(p);
                }
            }
        }
        files.sort();
        let mut compared = 0;
        for p in &files {
            let Ok(reference) = MjModel::from_xml(p) else {
                continue; // an include fragment, or a fixture that is meant to fail
            };
            let ours = compile(&mut parse(p).unwrap()).unwrap();
            let mjb = |m: &MjModel| {
                let mut b = vec![0u8; m.size()];
                m.save_to_buffer(&mut b).unwrap();
                b
            };
            assert!(
                mjb(&reference) == mjb(&ours),
                "{}: mjb differs",
                p.display()
            );
            let buffer = |m: &MjModel| {
                // SAFETY: `buffer` holds `nbuffer` bytes for as long as the model lives.
                unsafe {
                    std::slice::from_raw_parts(
                        m.ffi().buffer as *const u8,
                        m.ffi().nbuffer as usize,
                    )
                }
                .to_vec()
            };
            assert!(
                buffer(&reference) == buffer(&ours),
                "{}: buffer differs",
                p.display()
            );
            compared += 1;
        }
        assert!(compared >= 40, "only {compared} models compared");
    }

    /// An `mju_error` beneath the shim comes back as status 3 with its message, without
    /// entering envc's Rust handler; MuJoCo works as before afterwards, on the same thread.
    #[test]
    fn an_mju_error_beneath_the_shim_is_returned() {
        crate::mj::log::install();
        for _ in 0..3 {
            let mut buf = [0 as c_char; 1024];
            let msg = CString::new("a test error").unwrap();
            // SAFETY: a NUL-terminated message and a writable buffer of the length given.
            let status =
                unsafe { envc_raise_mju_error(msg.as_ptr(), buf.as_mut_ptr(), buf.len() as c_int) };
            assert_eq!(status, 3);
            assert_eq!(message(status, &buf), "a test error");
        }
        let hopper = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/gymnasium/hopper.xml");
        assert!(compile(&mut parse(&hopper).unwrap()).is_ok());
    }

    /// MuJoCo's own refusals keep their message (now whole: mujoco-rs cut it at 99 bytes).
    #[test]
    fn refusals_carry_mujocos_message() {
        let dir = std::env::temp_dir().join(format!("envc-catch-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let bad = dir.join("bad.xml");
        std::fs::write(
            &bad,
            "<mujoco><worldbody><geom size=\"0\"/></worldbody></mujoco>",
        )
        .unwrap();
        let e = compile(&mut parse(&bad).unwrap()).unwrap_err();
        assert!(e.contains("size 0 must be positive in geom"), "{e}");
        std::fs::write(&bad, "<mujoco><worldbody><bogus/></worldbody></mujoco>").unwrap();
        let e = parse(&bad).err().unwrap();
        assert!(e.contains("Schema violation: unrecognized element"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
