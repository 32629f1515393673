//! Where the extension finds MuJoCo 3.17.0 at run time, without LD_LIBRARY_PATH: first the
//! `mujoco` Python package beside it in site-packages (a dependency of `envc`, which carries
//! `libmujoco.so.3.17.0`), then the library scripts/setup.sh provisions for this checkout.
fn main() {
    println!("cargo::rerun-if-env-changed=MUJOCO_DYNAMIC_LINK_DIR");
    println!("cargo::rustc-link-arg=-Wl,-rpath,$ORIGIN/../mujoco");
    // The wheel (scripts/build-wheel.sh sets ENVC_WHEEL) names no path of the machine it was
    // built on.
    println!("cargo::rerun-if-env-changed=ENVC_WHEEL");
    if std::env::var_os("ENVC_WHEEL").is_none()
        && let Ok(dir) = std::env::var("MUJOCO_DYNAMIC_LINK_DIR")
    {
        println!("cargo::rustc-link-arg=-Wl,-rpath,{dir}");
    }
}
