//! Where the extension finds MuJoCo at run time, without LD_LIBRARY_PATH: first the `mujoco`
//! Python package beside it in site-packages (a dependency of `envc`, which carries
//! `libmujoco.so.VERSION`), then the library envc was built against in this checkout (envc's build
//! script hands its directory on as DEP_ENVC_MUJOCO_LIB_DIR).
fn main() {
    println!("cargo::rerun-if-env-changed=DEP_ENVC_MUJOCO_LIB_DIR");
    println!("cargo::rustc-link-arg=-Wl,-rpath,$ORIGIN/../mujoco");
    // The wheel (scripts/build-wheel.sh sets ENVC_WHEEL) names no path of the machine it was
    // built on.
    println!("cargo::rerun-if-env-changed=ENVC_WHEEL");
    if std::env::var_os("ENVC_WHEEL").is_none()
        && let Ok(dir) = std::env::var("DEP_ENVC_MUJOCO_LIB_DIR")
    {
        println!("cargo::rustc-link-arg=-Wl,-rpath,{dir}");
    }
}
