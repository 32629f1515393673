//! Staging directories owned by a lock, not by a pid. A collection claims
//! `<root>/.envc-staging/<stem>.<pid>.<nanos>/` by first creating the sibling `<…>.lock` (O_EXCL)
//! and holding an exclusive `flock` on it for its whole life. The kernel drops the lock when the
//! process dies however it dies, and the lock means the same thing in every PID namespace, every
//! container sharing the directory and (NFS) every host, where a pid means nothing. A sweeper
//! removes a staging directory only when it can take that lock itself; a directory without a lock
//! file is never removed (it cannot be proven abandoned).

use std::fs::{self, File, OpenOptions};
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use crate::error::{DatasetError, io};

const LOCK_EXT: &str = "lock";

/// A claimed staging directory; dropping it removes the directory, then the lock file, then
/// releases the lock.
pub(crate) struct Staging {
    root: PathBuf,
    dir: PathBuf,
    lock_path: PathBuf,
    lock: File,
    /// The directory, held open: a directory removed and recreated under the same name
    /// (`create_dir_all` by anyone) is not ours, and while we hold it its inode number cannot be
    /// reused by the new one.
    dir_handle: File,
}

fn id_of(m: &fs::Metadata) -> (u64, u64) {
    (m.dev(), m.ino())
}

/// Non-blocking exclusive lock (`flock`); `Ok(false)` when someone else holds it.
fn try_lock(f: &File) -> std::io::Result<bool> {
    match f.try_lock() {
        Ok(()) => Ok(true),
        Err(fs::TryLockError::WouldBlock) => Ok(false),
        Err(fs::TryLockError::Error(e)) => Err(e),
    }
}

/// Whether `path` still names the file `f` is open on (it may have been unlinked by a sweeper
/// between our open and our flock).
fn same_file(f: &File, path: &Path) -> bool {
    match (f.metadata(), fs::symlink_metadata(path)) {
        (Ok(a), Ok(b)) => id_of(&a) == id_of(&b),
        _ => false,
    }
}

impl Staging {
    /// Claim a fresh staging directory for `stem` (e.g. `random-v0`) under `root`.
    pub(crate) fn claim(root: &Path, stem: &str) -> Result<Staging, DatasetError> {
        let mut last = None;
        for attempt in 0..16u32 {
            // Another collection may remove the (empty) staging root at any moment: recreate it.
            fs::create_dir_all(root).map_err(io(root))?;
            let nanos = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_nanos())
                .unwrap_or(0);
            let name = format!("{stem}.{}.{nanos}{attempt}", std::process::id());
            let dir = root.join(&name);
            let lock_path = root.join(format!("{name}.{LOCK_EXT}"));
            let lock = match OpenOptions::new()
                .read(true)
                .write(true)
                .create_new(true)
                .open(&lock_path)
            {
                Ok(f) => f,
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::NotFound | std::io::ErrorKind::AlreadyExists
                    ) =>
                {
                    last = Some(e);
                    continue;
                }
                Err(e) => return Err(io(&lock_path)(e)),
            };
            // A sweeper may lock (and unlink) the fresh file before we do: then try a new name.
            if !try_lock(&lock).map_err(io(&lock_path))? || !same_file(&lock, &lock_path) {
                continue;
            }
            match fs::create_dir(&dir) {
                Ok(()) => {}
                Err(e) => {
                    let _ = fs::remove_file(&lock_path);
                    return Err(io(&dir)(e));
                }
            }
            let dir_handle = File::open(&dir).map_err(io(&dir))?;
            return Ok(Staging {
                root: root.to_path_buf(),
                dir,
                lock_path,
                lock,
                dir_handle,
            });
        }
        Err(io(root)(last.unwrap_or_else(|| {
            std::io::Error::other("could not claim a staging directory (lock contention)")
        })))
    }

    pub(crate) fn dir(&self) -> &Path {
        &self.dir
    }

    /// `Err(E1209)` unless the directory and its lock file are still the ones we claimed.
    pub(crate) fn check_owned(&self) -> Result<(), DatasetError> {
        if same_file(&self.dir_handle, &self.dir) && same_file(&self.lock, &self.lock_path) {
            Ok(())
        } else {
            Err(DatasetError::StagingLost {
                path: self.dir.clone(),
            })
        }
    }
}

/// Attempts at removing a staging directory that entries keep appearing in (20 ms apart).
const REMOVE_TRIES: u32 = 50;

impl Drop for Staging {
    fn drop(&mut self) {
        // Only what is still ours: never remove what someone else now owns.
        if same_file(&self.dir_handle, &self.dir) {
            // A sharded collection's worker that is still ending (killed, not yet gone) can add
            // an entry while the tree is being removed, which then fails on the non-empty
            // directory: a few more tries, briefly apart, remove what it added.
            for _ in 0..REMOVE_TRIES {
                if fs::remove_dir_all(&self.dir).is_ok() || !self.dir.exists() {
                    break;
                }
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
        }
        if same_file(&self.lock, &self.lock_path) {
            let _ = fs::remove_file(&self.lock_path);
        }
        // Fails (harmlessly) while other collections stage here.
        let _ = fs::remove_dir(&self.root);
        // The lock is released when `self.lock` closes.
    }
}

/// What [`sweep`] did.
#[derive(Default)]
pub(crate) struct Swept {
    /// Staging directories of collections that are gone (their lock was free), removed.
    pub removed: Vec<PathBuf>,
    /// Directories without a lock file (an older envc's, or not envc's), left alone.
    pub unlocked: Vec<PathBuf>,
}

/// Remove the staging directories of collections that are gone (their lock is free) under
/// `root`. Live collections, in any PID namespace or on any host sharing the directory, hold
/// their lock and are left alone, as is anything without a lock file.
pub(crate) fn sweep(root: &Path) -> Swept {
    let mut swept = Swept::default();
    let Ok(entries) = fs::read_dir(root) else {
        return swept;
    };
    let mut dirs = vec![];
    for e in entries.flatten() {
        let lock_path = e.path();
        if lock_path.extension().is_none_or(|x| x != LOCK_EXT) {
            if e.file_type().is_ok_and(|t| t.is_dir()) {
                dirs.push(lock_path);
            }
            continue;
        }
        let Ok(f) = OpenOptions::new().read(true).open(&lock_path) else {
            continue;
        };
        if !matches!(try_lock(&f), Ok(true)) || !same_file(&f, &lock_path) {
            continue;
        }
        let dir = lock_path.with_extension("");
        match fs::remove_dir_all(&dir) {
            Ok(()) => swept.removed.push(dir),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(_) => continue, // keep the lock file: the directory is still there
        }
        let _ = fs::remove_file(&lock_path);
    }
    // A claim creates its lock file before its directory, so a directory seen without one
    // was not made by this scheme.
    let lock_of = |d: &Path| PathBuf::from(format!("{}.{LOCK_EXT}", d.display()));
    swept.unlocked = dirs
        .into_iter()
        .filter(|d| !swept.removed.contains(d) && !lock_of(d).exists() && d.exists())
        .collect();
    swept.unlocked.sort();
    swept
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(tag: &str) -> PathBuf {
        let p = std::env::temp_dir().join(format!("envc-staging-{tag}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&p);
        p
    }

    #[test]
    fn a_held_lock_is_never_swept_a_free_one_is() {
        let root = tmp("sweep");
        let live = Staging::claim(&root, "x-v0").unwrap();
        fs::write(live.dir().join("episode"), b"data").unwrap();
        // A dead collection: a lock file nobody holds, and its directory.
        let dead = root.join("y-v0.1.2");
        fs::create_dir_all(dead.join("ds")).unwrap();
        fs::write(root.join("y-v0.1.2.lock"), b"").unwrap();
        // No lock file at all: cannot be proven abandoned.
        fs::create_dir_all(root.join("z-v0.3.4")).unwrap();
        let swept = sweep(&root);
        assert_eq!(swept.removed, vec![dead.clone()]);
        assert_eq!(swept.unlocked, vec![root.join("z-v0.3.4")]);
        assert!(live.dir().join("episode").is_file());
        assert!(!dead.exists() && !root.join("y-v0.1.2.lock").exists());
        assert!(root.join("z-v0.3.4").is_dir());
        live.check_owned().unwrap();
        let dir = live.dir().to_path_buf();
        drop(live);
        assert!(!dir.exists());
        let _ = fs::remove_dir_all(&root);
    }

    #[test]
    fn a_removed_directory_is_no_longer_owned_even_if_recreated() {
        let root = tmp("lost");
        let s = Staging::claim(&root, "x-v0").unwrap();
        fs::remove_dir_all(s.dir()).unwrap();
        fs::create_dir_all(s.dir()).unwrap();
        let e = s.check_owned().unwrap_err();
        assert_eq!(e.code(), "E1209");
        // Not ours any more: dropping leaves the recreated directory alone (its own lock file,
        // still ours, goes).
        let dir = s.dir().to_path_buf();
        drop(s);
        assert!(dir.is_dir());
        assert!(!PathBuf::from(format!("{}.lock", dir.display())).exists());
        let _ = fs::remove_dir_all(&root);
    }
}
