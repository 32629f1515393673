//! Where the bundled specs and models are: the directory holding `specs/` and `assets/`.
//!
//! Every build embeds both trees (`build.rs`), so an installed binary, a Python wheel or a crate
//! that depends on envc finds them without the source tree it was built from. The root is, in
//! this order:
//!
//! 1. a directory the host program names with [`set_root`] before first use (the Python package
//!    names its package data), or else `_bundle/` beside the program's own directory (the `envc`
//!    command inside the wheel is `envc/_bin/envc`, its data `envc/_bundle/`);
//! 2. the source tree the crate was compiled from, when it still exists and the running program
//!    was built inside it (the tests and `target/` binaries of a checkout read its files, so a
//!    spec edited there is what they run);
//! 3. the embedded copy, written once into a per-user cache directory named by its content hash
//!    (a temporary directory renamed into place, so concurrent processes never see half a copy).

use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock};

mod embedded {
    include!(concat!(env!("OUT_DIR"), "/bundle.rs"));
}

/// Where the bundle root came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Origin {
    /// Named by the host program ([`set_root`]): the Python package's data.
    Package,
    /// The source tree this build came from.
    SourceTree,
    /// The copy embedded in the binary, extracted into the user's cache.
    Embedded,
}

impl Origin {
    /// A short description for `envc info`.
    pub fn describe(self) -> &'static str {
        match self {
            Origin::Package => "the installed package's data",
            Origin::SourceTree => "the source tree envc was built from",
            Origin::Embedded => "the copy embedded in envc, extracted into the user cache",
        }
    }
}

/// The bundle root and its origin, or why there is none.
type Resolved = Result<(PathBuf, Origin), String>;

static NAMED: Mutex<Option<PathBuf>> = Mutex::new(None);
static ROOT: OnceLock<Resolved> = OnceLock::new();

/// Names the bundle root (a directory holding `specs/` and `assets/`). Must come before the
/// first lookup; afterwards it changes nothing and returns false.
pub fn set_root(dir: &Path) -> bool {
    if ROOT.get().is_some() {
        return false;
    }
    if let Ok(mut named) = NAMED.lock() {
        *named = Some(dir.to_path_buf());
    }
    true
}

/// The bundle root and where it came from.
pub fn root() -> Result<(&'static Path, Origin), &'static str> {
    match ROOT.get_or_init(resolve) {
        Ok((p, o)) => Ok((p.as_path(), *o)),
        Err(e) => Err(e.as_str()),
    }
}

/// The directory of the bundled specs (`<root>/specs`); a path that does not exist when there is
/// no bundle (every lookup then fails with E0601).
pub fn specs_dir() -> PathBuf {
    match root() {
        Ok((r, _)) => r.join("specs"),
        Err(_) => PathBuf::from("<no bundled specs>"),
    }
}

/// The hash of the embedded files (the extracted copy's directory name).
pub fn hash() -> &'static str {
    embedded::HASH
}

fn resolve() -> Resolved {
    if let Some(dir) = NAMED.lock().ok().and_then(|n| n.clone()) {
        let dir = dir.canonicalize().unwrap_or(dir);
        // An editable install names the checkout it lives in.
        let src = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .canonicalize();
        let origin = if src.is_ok_and(|s| s == dir) {
            Origin::SourceTree
        } else {
            Origin::Package
        };
        return Ok((dir, origin));
    }
    if let Some(dir) = beside_program() {
        return Ok((dir, Origin::Package));
    }
    if let Some(src) = source_tree() {
        return Ok((src, Origin::SourceTree));
    }
    extract()
}

/// `<program dir>/../_bundle`, when it holds the bundle.
fn beside_program() -> Option<PathBuf> {
    let exe = std::env::current_exe().ok()?.canonicalize().ok()?;
    let dir = exe.parent()?.parent()?.join("_bundle");
    (dir.join("specs").is_dir() && dir.join("assets").is_dir()).then_some(dir)
}

/// The source tree, if this program was built inside it and it is still there.
fn source_tree() -> Option<PathBuf> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .canonicalize()
        .ok()?;
    if !src.join("specs").is_dir() || !src.join("assets").is_dir() {
        return None;
    }
    let exe = std::env::current_exe().ok()?.canonicalize().ok()?;
    exe.starts_with(&src).then_some(src)
}

/// Where extracted copies live: `$XDG_CACHE_HOME/envc`, `~/.cache/envc`, else the temporary
/// directory.
fn cache_base() -> Vec<PathBuf> {
    let mut v = vec![];
    if let Some(x) = std::env::var_os("XDG_CACHE_HOME").filter(|x| !x.is_empty()) {
        v.push(PathBuf::from(x).join("envc"));
    }
    if let Some(h) = std::env::var_os("HOME").filter(|h| !h.is_empty()) {
        v.push(PathBuf::from(h).join(".cache").join("envc"));
    }
    v.push(std::env::temp_dir().join(format!("envc-{}", user_tag())));
    v
}

fn user_tag() -> String {
    std::env::var("USER")
        .ok()
        .filter(|u| !u.is_empty() && u.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or_else(|| "user".to_string())
}

fn extract() -> Resolved {
    let name = format!("bundle-{}-{}", env!("CARGO_PKG_VERSION"), embedded::HASH);
    let mut errors = vec![];
    let temp = std::env::temp_dir();
    for base in cache_base() {
        if let Err(e) = trusted_base(&base, base.starts_with(&temp)) {
            errors.push(format!("{}: {e}", base.display()));
            continue;
        }
        sweep(&base);
        let dest = base.join(&name);
        if dest.join("specs").is_dir() {
            // Verified once per process: an edited or planted file is not the bundle.
            if intact(&dest) {
                return Ok((dest, Origin::Embedded));
            }
            discard(&base, &dest);
        }
        match write_copy(&base, &dest) {
            Ok(()) if intact(&dest) => return Ok((dest, Origin::Embedded)),
            Ok(()) => errors.push(format!("{}: the extracted copy differs", dest.display())),
            Err(e) => errors.push(format!("{}: {e}", base.display())),
        }
    }
    Err(format!(
        "cannot write envc's bundled specs into a cache directory ({})",
        errors.join("; ")
    ))
}

/// A cache directory envc may trust: created if missing (private), a real directory (not a
/// link) owned by this user and writable by no other (in the shared temporary directory, where
/// another user could have made it first, not by its group either).
fn trusted_base(base: &Path, shared: bool) -> std::io::Result<()> {
    use std::os::unix::fs::{DirBuilderExt, MetadataExt};
    if std::fs::symlink_metadata(base).is_err() {
        std::fs::DirBuilder::new()
            .recursive(true)
            .mode(0o700)
            .create(base)?;
    }
    let meta = std::fs::symlink_metadata(base)?;
    // /proc/self belongs to the process's effective user.
    let me = std::fs::metadata("/proc/self")?.uid();
    let refuse = |why: &str| Err(std::io::Error::other(why.to_string()));
    if !meta.is_dir() {
        return refuse("not a directory (a symbolic link or a file)");
    }
    if meta.uid() != me {
        return refuse("owned by another user");
    }
    if meta.mode() & if shared { 0o022 } else { 0o002 } != 0 {
        return refuse("writable by other users");
    }
    Ok(())
}

/// Whether `dest` holds exactly the embedded files, byte for byte, and nothing else.
fn intact(dest: &Path) -> bool {
    for (rel, bytes) in embedded::FILES {
        let p = dest.join(rel);
        let regular = std::fs::symlink_metadata(&p)
            .is_ok_and(|m| m.is_file() && m.len() == bytes.len() as u64);
        if !regular || std::fs::read(&p).ok().as_deref() != Some(*bytes) {
            return false;
        }
    }
    count_files(dest).is_some_and(|n| n == embedded::FILES.len())
}

/// Files under `dir` (links not followed; None past a bound: not the bundle).
fn count_files(dir: &Path) -> Option<usize> {
    let mut n = 0usize;
    let mut dirs = vec![dir.to_path_buf()];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).ok()?.flatten() {
            let t = e.file_type().ok()?;
            if t.is_dir() {
                dirs.push(e.path());
            } else {
                n += 1;
            }
            if n > embedded::FILES.len() * 2 + 1000 {
                return None;
            }
        }
    }
    Some(n)
}

/// Moves a damaged copy aside (a rename, so no process sees it half removed), then removes it.
fn discard(base: &Path, dest: &Path) {
    let aside = base.join(format!(".tmp-{}-stale", std::process::id()));
    let _ = std::fs::remove_dir_all(&aside);
    if std::fs::rename(dest, &aside).is_ok() {
        let _ = std::fs::remove_dir_all(&aside);
    }
}

/// Removes the `.tmp-<pid>-*` directories of extractions whose process is gone (killed part-way).
fn sweep(base: &Path) {
    let Ok(read) = std::fs::read_dir(base) else {
        return;
    };
    for e in read.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(pid) = name
            .strip_prefix(".tmp-")
            .and_then(|r| r.split('-').next())
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        if pid != std::process::id() && !Path::new(&format!("/proc/{pid}")).exists() {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

/// Writes every embedded file into a fresh sibling of `dest`, then renames it into place. A
/// concurrent process that wins the rename leaves an identical copy, which is kept.
fn write_copy(base: &Path, dest: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(base)?;
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.subsec_nanos())
        .unwrap_or(0);
    let tmp = base.join(format!(".tmp-{}-{nanos}", std::process::id()));
    let result = (|| {
        for (rel, bytes) in embedded::FILES {
            let p = tmp.join(rel);
            if let Some(parent) = p.parent() {
                std::fs::create_dir_all(parent)?;
            }
            std::fs::write(&p, bytes)?;
        }
        std::fs::rename(&tmp, dest)
    })();
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&tmp);
        if dest.join("specs").is_dir() {
            return Ok(());
        }
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embeds_every_bundled_spec_and_model() {
        let names: Vec<&str> = embedded::FILES.iter().map(|(n, _)| *n).collect();
        for want in [
            "specs/gymnasium/ant.toml",
            "assets/gymnasium/ant.xml",
            "specs/mamujoco/half_cheetah.toml",
        ] {
            assert!(names.contains(&want), "{want} is not embedded");
        }
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        for (rel, bytes) in embedded::FILES {
            assert_eq!(std::fs::read(src.join(rel)).unwrap(), *bytes, "{rel}");
        }
    }

    #[test]
    fn an_edited_or_planted_copy_is_not_intact_and_leftovers_are_swept() {
        let base = std::env::temp_dir().join(format!("envc-bundle-trust-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&base);
        let dest = base.join("copy");
        write_copy(&base, &dest).unwrap();
        assert!(intact(&dest));
        let hopper = dest.join("specs/gymnasium/hopper.toml");
        let text = std::fs::read_to_string(&hopper).unwrap();
        std::fs::write(&hopper, text.replace("frame_skip", "frame_skip ")).unwrap();
        assert!(!intact(&dest));
        std::fs::write(&hopper, text).unwrap();
        assert!(intact(&dest));
        std::fs::write(
            dest.join("specs/gymnasium/extra.toml"),
            "[env]\nid = \"X-v0\"\n",
        )
        .unwrap();
        assert!(!intact(&dest));
        discard(&base, &dest);
        assert!(!dest.exists());
        // A killed extraction's directory (a process that no longer runs) is swept; ours is not.
        let dead = base.join(".tmp-4294967-1");
        let ours = base.join(format!(".tmp-{}-1", std::process::id()));
        std::fs::create_dir_all(&dead).unwrap();
        std::fs::create_dir_all(&ours).unwrap();
        sweep(&base);
        assert!(!dead.exists() && ours.exists());
        // The cache base must be this user's and private.
        assert!(trusted_base(&base, true).is_ok());
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&base, std::fs::Permissions::from_mode(0o770)).unwrap();
        assert!(trusted_base(&base, true).is_err());
        assert!(trusted_base(&base, false).is_ok());
        std::fs::set_permissions(&base, std::fs::Permissions::from_mode(0o777)).unwrap();
        assert!(trusted_base(&base, false).is_err());
        let link = base.with_extension("link");
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink(&base, &link).unwrap();
        assert!(trusted_base(&link, false).is_err());
        let _ = std::fs::remove_file(&link);
        let _ = std::fs::remove_dir_all(&base);
    }

    #[test]
    fn extracted_copy_equals_the_source_tree() {
        let base = std::env::temp_dir().join(format!("envc-bundle-test-{}", std::process::id()));
        let dest = base.join("copy");
        write_copy(&base, &dest).unwrap();
        // a second writer finds the copy in place and keeps it
        write_copy(&base, &dest).unwrap();
        let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        for (rel, _) in embedded::FILES {
            assert_eq!(
                std::fs::read(dest.join(rel)).unwrap(),
                std::fs::read(src.join(rel)).unwrap(),
                "{rel}"
            );
        }
        std::fs::remove_dir_all(&base).unwrap();
    }
}
