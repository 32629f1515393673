//! Embed an rpath to the MuJoCo library provisioned by scripts/setup.sh, so binaries, tests and
//! examples of this package run from any directory without LD_LIBRARY_PATH. (A dependency's
//! link args do not propagate, so each package that links MuJoCo has this file.)
fn main() {
    println!("cargo::rerun-if-env-changed=MUJOCO_DYNAMIC_LINK_DIR");
    // Without it, MuJoCo comes from pkg-config and the loader's cache (scripts/install-mujoco.sh).
    if let Ok(dir) = std::env::var("MUJOCO_DYNAMIC_LINK_DIR") {
        println!("cargo::rustc-link-arg=-Wl,-rpath,{dir}");
    }
}
