//! Embeds the bundled specs and models (`specs/`, `assets/` of the source tree) into the crate,
//! so a binary or library built from it finds them wherever it is installed (`envspec::bundle`).
//! Written by hand: `include_bytes!` over a generated list is all it takes, and the crates that
//! embed directories pull in proc-macro stacks for the same result.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let root = manifest.join("..");
    let mut files = vec![];
    for top in ["specs", "assets"] {
        let dir = root.join(top);
        // A directory makes cargo rescan every file under it for changes.
        println!("cargo::rerun-if-changed={}", dir.display());
        walk(&root, &dir, &mut files);
    }
    files.sort();
    // FNV-1a over names and contents: the extracted copy's directory name, so two builds with
    // different specs never share (or half-overwrite) one copy.
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut mix = |bytes: &[u8]| {
        for b in bytes {
            hash ^= u64::from(*b);
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
    };
    let mut out =
        String::from("/// Every bundled file: its path under the bundle root, and its bytes.\n");
    out.push_str("pub(crate) static FILES: &[(&str, &[u8])] = &[\n");
    for (rel, abs) in &files {
        let bytes = std::fs::read(abs).expect("a bundled file is readable");
        mix(rel.as_bytes());
        mix(&(bytes.len() as u64).to_le_bytes());
        mix(&bytes);
        writeln!(
            out,
            "    ({rel:?}, include_bytes!({:?})),",
            abs.display().to_string()
        )
        .expect("writing to a String");
    }
    out.push_str("];\n");
    writeln!(
        out,
        "/// A hash of every name and byte above.\npub(crate) const HASH: &str = \"{hash:016x}\";"
    )
    .expect("writing to a String");
    let dest = PathBuf::from(std::env::var("OUT_DIR").expect("set by cargo")).join("bundle.rs");
    std::fs::write(dest, out).expect("OUT_DIR is writable");
}

fn walk(root: &Path, dir: &Path, out: &mut Vec<(String, PathBuf)>) {
    let Ok(read) = std::fs::read_dir(dir) else {
        return;
    };
    for e in read.flatten() {
        let p = e.path();
        let name = e.file_name();
        if name.to_string_lossy().starts_with('.') {
            continue;
        }
        if p.is_dir() {
            walk(root, &p, out);
        } else if p.is_file() {
            let rel = p
                .strip_prefix(root)
                .expect("walked under root")
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join("/");
            let abs = p.canonicalize().unwrap_or(p);
            out.push((rel, abs));
        }
    }
}
