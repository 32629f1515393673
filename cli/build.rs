//! Embed an rpath to the MuJoCo library envc was built against (its build script hands the
//! directory on as DEP_ENVC_MUJOCO_LIB_DIR), so binaries, tests and examples of this package run
//! from any directory without LD_LIBRARY_PATH. (A dependency's link args do not propagate, so each
//! package that links MuJoCo has this file.)
fn main() {
    println!("cargo::rerun-if-env-changed=DEP_ENVC_MUJOCO_LIB_DIR");
    // Without it, MuJoCo comes from pkg-config and the loader's cache (scripts/install-mujoco.sh).
    if let Ok(dir) = std::env::var("DEP_ENVC_MUJOCO_LIB_DIR") {
        println!("cargo::rustc-link-arg=-Wl,-rpath,{dir}");
    }
}
