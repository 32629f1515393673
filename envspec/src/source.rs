//! The one reader of spec inputs. Every file a spec pulls in (the spec's TOML, a maze's map, a
//! multi-agent spec's base, the MJCF and its `<include>`s, a URDF, the mesh and texture files a
//! model names) is read through here, from the disk or from a git revision, and every read is
//! recorded (path and a hash of the bytes), the way sqlx records the files its macros read.
//!
//! A [`Reader`] is installed for the duration of a closure ([`Reader::run`]); the readers of
//! `envspec` consult the installed one. Without one, files come from the disk and nothing is
//! recorded (the runtime, the Python package). Codegen runs its expansion inside a reader and
//! tracks the recorded files; `envc diff REV:path` mounts the revision under a directory, so the
//! old side's spec, model and includes are read by the same readers with the same limits.

use std::cell::RefCell;
use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use crate::diagnostic::{Code, Diagnostic, Location, SourceFile};
use crate::limits::ReadError;

/// Where the files under a mount come from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// The file system, as it is.
    Disk,
    /// `git show REV:path` in the repository `repo` (path relative to the repository root).
    /// Each file read is also written under the mount, at its path, because MuJoCo reads the
    /// model and its includes and meshes itself when `envc diff` compiles it.
    GitRev {
        /// The repository's root directory.
        repo: PathBuf,
        /// The revision, as `git show` takes it (a commit, a branch, `HEAD~1`).
        rev: String,
    },
}

/// One file a spec read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileRead {
    /// The path as the reader named it (joined onto the including file's directory).
    pub path: PathBuf,
    /// FNV-1a 64 of the bytes envspec parsed; None for a mesh or texture whose size only was
    /// checked (MuJoCo reads those; no generated code depends on them).
    pub hash: Option<u64>,
}

/// The installed source of spec inputs: mounts and the record of what was read.
#[derive(Debug, Default)]
pub struct Reader {
    /// Directories whose files come from another source, longest match first.
    mounts: Vec<(PathBuf, Source)>,
    record: Vec<FileRead>,
}

thread_local! {
    static CURRENT: RefCell<Option<Reader>> = const { RefCell::new(None) };
}

impl Reader {
    /// A reader of the disk (recording what it reads).
    pub fn disk() -> Reader {
        Reader::default()
    }

    /// Read the files under `root` from `source` instead of the disk.
    pub fn mount(mut self, root: impl Into<PathBuf>, source: Source) -> Reader {
        self.mounts.push((root.into(), source));
        self.mounts
            .sort_by_key(|(r, _)| std::cmp::Reverse(r.components().count()));
        self
    }

    /// Run `f` with this reader installed on the current thread (the previous one, if any, is
    /// restored afterwards, also when `f` panics).
    pub fn run<T>(&mut self, f: impl FnOnce() -> T) -> T {
        struct Restore<'a> {
            reader: &'a mut Reader,
            outer: Option<Reader>,
        }
        impl Drop for Restore<'_> {
            fn drop(&mut self) {
                let mine = CURRENT.with(|c| c.replace(self.outer.take()));
                *self.reader = mine.unwrap_or_default();
            }
        }
        let outer = CURRENT.with(|c| c.replace(Some(std::mem::take(self))));
        let _restore = Restore {
            reader: self,
            outer,
        };
        f()
    }

    /// Every file read so far, in the order first read (each path once).
    pub fn files(&self) -> &[FileRead] {
        &self.record
    }

    fn note(&mut self, path: &Path, bytes: Option<&[u8]>) {
        let hash = bytes.map(fnv1a);
        match self.record.iter_mut().find(|r| r.path == path) {
            Some(r) => r.hash = hash.or(r.hash),
            None => self.record.push(FileRead {
                path: path.to_path_buf(),
                hash,
            }),
        }
    }

    /// The mount `path` is under, and the path relative to its root.
    fn mounted(&self, path: &Path) -> Option<(&Path, &Source, PathBuf)> {
        self.mounts.iter().find_map(|(root, source)| {
            let rel = path.strip_prefix(root).ok()?;
            Some((root.as_path(), source, crate::path::normalize(rel)))
        })
    }
}

/// Run `f` recording every file it reads, under the installed reader's mounts, and return them
/// with its result (also recorded by the installed reader, as if read directly). What a spec
/// records about its inputs (`ResolvedSpec::inputs`) comes from here.
pub fn recorded<T>(f: impl FnOnce() -> T) -> (T, Vec<FileRead>) {
    let mounts = CURRENT.with(|c| {
        c.borrow()
            .as_ref()
            .map(|r| r.mounts.clone())
            .unwrap_or_default()
    });
    let mut inner = Reader {
        mounts,
        record: vec![],
    };
    let out = inner.run(f);
    CURRENT.with(|c| {
        if let Some(outer) = c.borrow_mut().as_mut() {
            for r in &inner.record {
                match outer.record.iter_mut().find(|o| o.path == r.path) {
                    Some(o) => o.hash = r.hash.or(o.hash),
                    None => outer.record.push(r.clone()),
                }
            }
        }
    });
    (out, inner.record)
}

/// FNV-1a, 64 bits: a stable fingerprint of a file's bytes (not a security hash).
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Where a read goes: the disk, or a file at a git revision (materialised under its mount).
enum Route {
    Disk,
    Git {
        repo: PathBuf,
        rev: String,
        rel: PathBuf,
        dest: PathBuf,
    },
}

fn route(path: &Path) -> Route {
    CURRENT.with(|c| {
        let c = c.borrow();
        match c.as_ref().and_then(|r| r.mounted(path)) {
            Some((root, Source::GitRev { repo, rev }, rel)) => Route::Git {
                repo: repo.clone(),
                rev: rev.clone(),
                dest: root.join(&rel),
                rel,
            },
            _ => Route::Disk,
        }
    })
}

fn record(path: &Path, bytes: Option<&[u8]>) {
    CURRENT.with(|c| {
        if let Some(r) = c.borrow_mut().as_mut() {
            r.note(path, bytes);
        }
    });
}

/// `git -C repo ARGS`, its stdout, or its stderr as the error.
fn git(repo: &Path, args: &[&str]) -> Result<Vec<u8>, ReadError> {
    let out = Command::new("git")
        .arg("-C")
        .arg(repo)
        .args(args)
        .output()
        .map_err(ReadError::Io)?;
    if !out.status.success() {
        let msg = format!(
            "git {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        );
        return Err(ReadError::Io(std::io::Error::new(
            std::io::ErrorKind::NotFound,
            msg,
        )));
    }
    Ok(out.stdout)
}

/// A path that leaves the mount (`../x`) is not in the revision's tree, and is never written
/// outside the mount.
fn outside(rel: &Path) -> Result<(), ReadError> {
    match rel.components().next() {
        Some(std::path::Component::ParentDir) => Err(ReadError::Io(std::io::Error::new(
            std::io::ErrorKind::NotFound,
            format!("{} is outside the repository", rel.display()),
        ))),
        _ => Ok(()),
    }
}

fn object(rev: &str, rel: &Path) -> String {
    format!("{rev}:{}", rel.display())
}

/// The file at a revision, within `limit` bytes (its size is asked first), written under the
/// mount for MuJoCo.
fn git_bytes(
    repo: &Path,
    rev: &str,
    rel: &Path,
    dest: &Path,
    limit: u64,
) -> Result<Vec<u8>, ReadError> {
    outside(rel)?;
    let obj = object(rev, rel);
    let kind = git(repo, &["cat-file", "-t", &obj])?;
    if String::from_utf8_lossy(&kind).trim() != "blob" {
        return Err(ReadError::NotAFile("directory"));
    }
    let size = git(repo, &["cat-file", "-s", &obj])?;
    let size: u64 = String::from_utf8_lossy(&size).trim().parse().unwrap_or(0);
    if size > limit {
        return Err(ReadError::TooLarge { limit });
    }
    let bytes = git(repo, &["show", &obj])?;
    if let Some(dir) = dest.parent() {
        std::fs::create_dir_all(dir).map_err(ReadError::Io)?;
    }
    std::fs::write(dest, &bytes).map_err(ReadError::Io)?;
    Ok(bytes)
}

/// Read a file's bytes, at most `limit` of them (the read is bounded, so a file that grows while
/// it is read cannot exhaust memory), and record it.
pub fn read_bytes(path: &Path, limit: u64) -> Result<Vec<u8>, ReadError> {
    let bytes = match route(path) {
        Route::Disk => {
            crate::limits::check_file(path, limit)?;
            let mut bytes = vec![];
            std::fs::File::open(path)
                .and_then(|f| f.take(limit + 1).read_to_end(&mut bytes))
                .map_err(ReadError::Io)?;
            if bytes.len() as u64 > limit {
                return Err(ReadError::TooLarge { limit });
            }
            bytes
        }
        Route::Git {
            repo,
            rev,
            rel,
            dest,
        } => git_bytes(&repo, &rev, &rel, &dest, limit)?,
    };
    record(path, Some(&bytes));
    Ok(bytes)
}

/// Read a UTF-8 text file of at most `limit` bytes, and record it.
pub fn read_text(path: &Path, limit: u64) -> Result<String, ReadError> {
    String::from_utf8(read_bytes(path, limit)?).map_err(|e| ReadError::NotUtf8 {
        offset: e.utf8_error().valid_up_to(),
    })
}

/// Whether a file a model names exists (a missing mesh is MuJoCo's to report).
pub fn exists(path: &Path) -> bool {
    match route(path) {
        Route::Disk => path.exists(),
        Route::Git { repo, rev, rel, .. } => {
            outside(&rel).is_ok() && git(&repo, &["cat-file", "-e", &object(&rev, &rel)]).is_ok()
        }
    }
}

/// Check a file that MuJoCo, not envspec, reads (a mesh, texture, heightfield or skin): a regular
/// file of at most `limit` bytes, without opening it on disk (opening a FIFO blocks). Recorded
/// without a hash; at a git revision it is written under the mount for MuJoCo.
pub fn check_asset(path: &Path, limit: u64) -> Result<(), ReadError> {
    match route(path) {
        Route::Disk => crate::limits::check_file(path, limit)?,
        Route::Git {
            repo,
            rev,
            rel,
            dest,
        } => {
            git_bytes(&repo, &rev, &rel, &dest, limit)?;
        }
    }
    record(path, None);
    Ok(())
}

/// Read a text file for a reader that quotes it, within `limit` bytes, through the one source of
/// spec inputs ([`crate::source`]: the disk or a git revision, recorded). A file that is not UTF-8
/// is diagnosed with `code` at the line and column of its first bad byte (`what` names the file's
/// role, e.g. "spec"); `unreadable` words any other failure.
pub fn read_source(
    path: &Path,
    limit: u64,
    code: Code,
    what: &str,
    unreadable: impl FnOnce(ReadError) -> Diagnostic,
) -> Result<Arc<SourceFile>, Diagnostic> {
    let bytes = read_bytes(path, limit).map_err(unreadable)?;
    let (at, bytes) = match String::from_utf8(bytes) {
        Ok(text) => return Ok(SourceFile::new(path, text)),
        // The lossy text equals the file up to the first bad byte, so the offset holds, and the
        // line can be shown (U+FFFD where the bad bytes are).
        Err(e) => (e.utf8_error().valid_up_to(), e.into_bytes()),
    };
    let at = at.min(bytes.len());
    let len = match std::str::from_utf8(&bytes[at..]) {
        Err(e) => e.error_len().unwrap_or(bytes.len() - at),
        Ok(_) => 0,
    };
    let bad = bytes[at..at + len.min(4)]
        .iter()
        .map(|b| format!("0x{b:02x}"))
        .collect::<Vec<_>>()
        .join(" ");
    let file = SourceFile::new(path, String::from_utf8_lossy(&bytes).into_owned());
    Err(
        Diagnostic::new(code, format!("the {what} file is not UTF-8 text"))
            .at(Location::new(&file, at..at + '\u{fffd}'.len_utf8()))
            .label(format!("invalid UTF-8 byte {bad}"))
            .help("save the file as UTF-8"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_the_published_vectors() {
        // The FNV reference test vectors for FNV-1a, 64 bits.
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn a_reader_records_each_file_once_and_restores_the_outer_one() {
        let dir = std::env::temp_dir().join(format!("envspec-source-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("a.toml");
        std::fs::write(&file, "foobar").unwrap();
        let mut outer = Reader::disk();
        let mut inner = Reader::disk();
        outer.run(|| {
            read_text(&file, 100).unwrap();
            inner.run(|| read_text(&file, 100).unwrap());
            read_text(&file, 100).unwrap();
        });
        for r in [&outer, &inner] {
            assert_eq!(r.files().len(), 1);
            assert_eq!(r.files()[0].path, file);
            assert_eq!(r.files()[0].hash, Some(0x8594_4171_f739_67e8));
        }
        // Outside a reader nothing is recorded; a missing file is an error.
        assert!(read_text(&dir.join("none"), 100).is_err());
        assert_eq!(outer.files().len(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
