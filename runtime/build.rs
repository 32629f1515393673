//! Embed an rpath to the MuJoCo library of the version this build is for (scripts/setup.sh's in the
//! workspace: MUJOCO_DYNAMIC_LINK_DIR for 3.17.0, MUJOCO_4_0_1_DYNAMIC_LINK_DIR for feature
//! `mujoco-4.0.1`), so binaries, tests and examples of this package run from any directory without
//! LD_LIBRARY_PATH; without it, MuJoCo comes from pkg-config and the loader's cache. The directory
//! is handed on as DEP_ENVC_MUJOCO_LIB_DIR: a dependency's link args do not propagate, so each
//! package that links MuJoCo embeds it too. Also build the C++ shim that catches MuJoCo's C++
//! exceptions (`csrc/mujoco_catch.cc`, `src/mj/mod.rs`'s `catch`) against that version's headers.

/// The MuJoCo version built for, and the prefix of its environment variables.
fn version() -> (&'static str, &'static str) {
    // (CARGO_FEATURE_* keeps a feature's dots, so the list of features is read instead.)
    let features = std::env::var("CARGO_CFG_FEATURE").unwrap_or_default();
    if features.split(',').any(|f| f == "mujoco-4.0.1") {
        ("4.0.1", "MUJOCO_4_0_1_")
    } else {
        ("3.17.0", "MUJOCO_")
    }
}

fn main() {
    let (version, prefix) = version();
    println!("cargo::rerun-if-env-changed={prefix}DYNAMIC_LINK_DIR");
    println!("cargo::rerun-if-env-changed={prefix}INCLUDE_DIR");
    println!("cargo::rerun-if-changed=csrc/mujoco_catch.cc");
    if let Ok(dir) = std::env::var(format!("{prefix}DYNAMIC_LINK_DIR")) {
        println!("cargo::rustc-link-arg=-Wl,-rpath,{dir}");
        println!("cargo::metadata=lib_dir={dir}");
    }
    let include = mujoco_include(version, prefix).unwrap_or_else(|| {
        panic!(
            "envc needs MuJoCo {version}'s headers and library, and found neither. Install them in \
             one of these ways, then build again:\n\
             - `python3 -m pip install mujoco=={version}`, then `scripts/install-mujoco.sh` from \
             envc's repository (as root: /usr/local, found through pkg-config);\n\
             - set {prefix}DYNAMIC_LINK_DIR=/path/to/mujoco/lib and \
             {prefix}INCLUDE_DIR=/path/to/mujoco/include;\n\
             - any MuJoCo {version} install with a `mujoco.pc` on the pkg-config path."
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

/// The directory holding `mujoco/mujoco.h`: `{prefix}INCLUDE_DIR`, then the checkout's copy
/// (scripts/setup.sh, scripts/mujoco.sh), then pkg-config, then the `mujoco` Python package of
/// `python3` when it is that version.
fn mujoco_include(version: &str, prefix: &str) -> Option<std::path::PathBuf> {
    let has_header = |d: &std::path::Path| d.join("mujoco").join("mujoco.h").is_file();
    if let Ok(dir) = std::env::var(format!("{prefix}INCLUDE_DIR")) {
        return Some(dir.into());
    }
    let third_party = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../third_party");
    let checkout = if version == "3.17.0" {
        third_party.join("mujoco/include")
    } else {
        third_party.join(format!("mujoco-{version}/include"))
    };
    if has_header(&checkout) {
        return Some(checkout);
    }
    if let Ok(lib) = pkg_config::Config::new()
        .cargo_metadata(false)
        .exactly_version(version)
        .probe("mujoco")
        && let Some(d) = lib.include_paths.into_iter().find(|d| has_header(d))
    {
        return Some(d);
    }
    let out = std::process::Command::new("python3")
        .args([
            "-c",
            "import mujoco, os; print(mujoco.__version__); \
             print(os.path.join(os.path.dirname(mujoco.__file__), 'include'))",
        ])
        .output()
        .ok()?;
    let out = String::from_utf8(out.stdout).ok()?;
    let mut lines = out.lines();
    (lines.next()? == version).then_some(())?;
    let dir = std::path::PathBuf::from(lines.next()?.trim());
    has_header(&dir).then_some(dir)
}
