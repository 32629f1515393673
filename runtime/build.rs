//! Embed an rpath to the MuJoCo library provisioned by scripts/setup.sh, so binaries, tests and
//! examples of this package run from any directory without LD_LIBRARY_PATH. (A dependency's
//! link args do not propagate, so each package that links MuJoCo has this file.) Also build the
//! C++ shim that catches MuJoCo's C++ exceptions (`csrc/mujoco_catch.cc`, `mujoco_catch.rs`).
fn main() {
    println!("cargo::rerun-if-env-changed=MUJOCO_DYNAMIC_LINK_DIR");
    println!("cargo::rerun-if-env-changed=MUJOCO_INCLUDE_DIR");
    println!("cargo::rerun-if-changed=csrc/mujoco_catch.cc");
    match std::env::var("MUJOCO_DYNAMIC_LINK_DIR") {
        Ok(dir) => println!("cargo::rustc-link-arg=-Wl,-rpath,{dir}"),
        Err(_) => println!("cargo::warning=MUJOCO_DYNAMIC_LINK_DIR is unset: run scripts/setup.sh"),
    }
    // .cargo/config.toml sets it; the fallback is where scripts/setup.sh puts the headers.
    let include = std::env::var("MUJOCO_INCLUDE_DIR").unwrap_or_else(|_| {
        format!(
            "{}/../third_party/mujoco/include",
            env!("CARGO_MANIFEST_DIR")
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
