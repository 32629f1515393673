//! Embed an rpath to the MuJoCo library named by MUJOCO_DYNAMIC_LINK_DIR (scripts/setup.sh's, in
//! the workspace), so binaries, tests and examples of this package run from any directory without
//! LD_LIBRARY_PATH; without it, MuJoCo comes from pkg-config and the loader's cache. (A dependency's
//! link args do not propagate, so each package that links MuJoCo has this file.) Also build the
//! C++ shim that catches MuJoCo's C++ exceptions (`csrc/mujoco_catch.cc`, `mujoco_catch.rs`).
fn main() {
    println!("cargo::rerun-if-env-changed=MUJOCO_DYNAMIC_LINK_DIR");
    println!("cargo::rerun-if-env-changed=MUJOCO_INCLUDE_DIR");
    println!("cargo::rerun-if-changed=csrc/mujoco_catch.cc");
    if let Ok(dir) = std::env::var("MUJOCO_DYNAMIC_LINK_DIR") {
        println!("cargo::rustc-link-arg=-Wl,-rpath,{dir}");
    }
    let include = mujoco_include().unwrap_or_else(|| {
        panic!(
            "envc needs MuJoCo 3.17.0's headers and library, and found neither. Install them in \
             one of these ways, then build again:\n\
             - `python3 -m pip install mujoco==3.17.0`, then `scripts/install-mujoco.sh` from \
             envc's repository (as root: /usr/local, found through pkg-config);\n\
             - set MUJOCO_DYNAMIC_LINK_DIR=/path/to/mujoco/lib and \
             MUJOCO_INCLUDE_DIR=/path/to/mujoco/include;\n\
             - any MuJoCo 3.17.0 install with a `mujoco.pc` on the pkg-config path."
        )
    });
    cc::Build::new()
        .cpp(true)
        .std("c++17")
        // no landing pads of its own: the catching is done by its own personality routine
        .flag("-fno-exceptions")
        .include(include)
        .file("csrc/mujoco_catch.cc")
        .warnings(true)
        .compile("envc_mujoco_catch");
}

/// The directory holding `mujoco/mujoco.h`: MUJOCO_INCLUDE_DIR, then the checkout's copy
/// (scripts/setup.sh), then pkg-config, then the `mujoco` Python package of `python3`.
fn mujoco_include() -> Option<std::path::PathBuf> {
    let has_header = |d: &std::path::Path| d.join("mujoco").join("mujoco.h").is_file();
    if let Ok(dir) = std::env::var("MUJOCO_INCLUDE_DIR") {
        return Some(dir.into());
    }
    let checkout =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../third_party/mujoco/include");
    if has_header(&checkout) {
        return Some(checkout);
    }
    if let Ok(lib) = pkg_config::Config::new()
        .cargo_metadata(false)
        .exactly_version("3.17.0")
        .probe("mujoco")
        && let Some(d) = lib.include_paths.into_iter().find(|d| has_header(d))
    {
        return Some(d);
    }
    let out = std::process::Command::new("python3")
        .args([
            "-c",
            "import mujoco, os; print(os.path.join(os.path.dirname(mujoco.__file__), 'include'))",
        ])
        .output()
        .ok()?;
    let dir = std::path::PathBuf::from(String::from_utf8(out.stdout).ok()?.trim());
    has_header(&dir).then_some(dir)
}
