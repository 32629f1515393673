//! Output files (`--out`): written whole to a hidden temporary file beside the target, synced, and
//! renamed over it, so an existing file is either left exactly as it was or replaced whole, never
//! truncated or half-written (a full disk, a kill). A killed run's temporary (hidden, its `flock`
//! free) is removed by the next run writing the same file. An output that is one of the command's
//! inputs is refused before anything runs. Codes E1410 and E1411 (docs/errors.md).

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Seek, SeekFrom, Write};
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use anyhow::{Result, bail};

/// `Err(E1411)` when `out` is the same file as one of `inputs` (`(flag, path)`), by device and
/// inode, so a symlink or a hard link to the input counts as the input.
pub fn refuse_input(out: &Path, inputs: &[(&str, &Path)]) -> Result<()> {
    let Ok(o) = fs::metadata(out) else {
        return Ok(()); // nothing there yet: cannot be an input
    };
    for (flag, input) in inputs {
        if let Ok(i) = fs::metadata(input)
            && (i.dev(), i.ino()) == (o.dev(), o.ino())
        {
            bail!(
                "error[E1411]: --out {} is the same file as {flag} {}; the output would replace the input, so write it elsewhere",
                out.display(),
                input.display()
            );
        }
    }
    Ok(())
}

fn cannot_write(target: &Path, existed: bool, e: &io::Error) -> anyhow::Error {
    anyhow::anyhow!(
        "error[E1410]: cannot write {}: {e}; {}",
        target.display(),
        if existed {
            "the existing file is unchanged"
        } else {
            "nothing was written"
        }
    )
}

/// Non-blocking exclusive lock (`flock`).
fn try_lock(f: &File) -> bool {
    f.try_lock().is_ok()
}

/// Remove temporaries `<dir>/<prefix>….tmp` left by killed runs (their lock is free).
fn sweep_temps(dir: &Path, prefix: &str) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let name = name.to_string_lossy();
        if !(name.starts_with(prefix) && name.ends_with(".tmp")) {
            continue;
        }
        if let Ok(f) = File::open(e.path())
            && try_lock(&f)
        {
            let _ = fs::remove_file(e.path());
        }
    }
}

/// A writer that keeps the first I/O error and swallows what follows, so a library writing
/// through it (the zip writer of `.npz` files, which prints its failures from `Drop`) sees
/// success, and the error is reported once, cleanly, by [`Output::commit`].
pub struct Sticky {
    inner: BufWriter<File>,
    error: Option<io::Error>,
    /// Position as the writer believes it, kept once writes are swallowed.
    pos: u64,
}

impl Sticky {
    fn fail(&mut self, e: io::Error) {
        if self.error.is_none() {
            self.error = Some(e);
        }
    }
}

impl Write for Sticky {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        if self.error.is_none() {
            match self.inner.write_all(buf) {
                Ok(()) => {}
                Err(e) => self.fail(e),
            }
        }
        self.pos += buf.len() as u64;
        Ok(buf.len())
    }
    fn flush(&mut self) -> io::Result<()> {
        if self.error.is_none()
            && let Err(e) = self.inner.flush()
        {
            self.fail(e);
        }
        Ok(())
    }
}

impl Seek for Sticky {
    fn seek(&mut self, to: SeekFrom) -> io::Result<u64> {
        if self.error.is_none() {
            match self.inner.seek(to) {
                Ok(p) => self.pos = p,
                Err(e) => self.fail(e),
            }
            if self.error.is_none() {
                return Ok(self.pos);
            }
        }
        // The file is lost anyway: keep positions consistent for the writer.
        self.pos = match to {
            SeekFrom::Start(p) => p,
            SeekFrom::Current(d) => self.pos.saturating_add_signed(d),
            SeekFrom::End(d) => self.pos.saturating_add_signed(d),
        };
        Ok(self.pos)
    }
}

/// The destination of one output file; dropping it without [`Output::commit`] removes the
/// temporary file and leaves the target untouched.
pub struct Output {
    /// Where the file goes (a symlink's target, so the link stays a link).
    target: PathBuf,
    /// What the user named, for messages.
    shown: PathBuf,
    tmp: PathBuf,
    existed: Option<fs::Permissions>,
    committed: bool,
}

impl Output {
    /// Start writing `path`: returns the destination and the writer of the temporary file.
    pub fn create(path: &Path) -> Result<(Output, Sticky)> {
        let existing = fs::metadata(path).ok();
        // The finished file is renamed over the target: over a device (`/dev/null`), a FIFO or a
        // socket that would replace the node itself, for every program on the machine.
        if let Some(m) = existing.as_ref().filter(|m| !m.is_file()) {
            bail!(
                "error[E1410]: cannot write {}: it is {}, not a regular file; envc writes an output whole and renames it into place",
                path.display(),
                if m.is_dir() {
                    "a directory"
                } else {
                    "a device, FIFO or socket"
                }
            );
        }
        let target = match existing {
            Some(_) => fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf()),
            None => path.to_path_buf(),
        };
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let name = target
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "out".into());
        let prefix = format!(".{name}.envc-");
        sweep_temps(&dir, &prefix);
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos())
            .unwrap_or(0);
        let tmp = dir.join(format!("{prefix}{}-{nanos}.tmp", std::process::id()));
        let existed = existing.map(|m| m.permissions());
        let file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(|e| cannot_write(path, existed.is_some(), &e))?;
        // Held until the file is renamed or removed: a later run removes only temporaries whose
        // lock it can take (a killed run's), never a running one's, in any PID namespace.
        if !try_lock(&file) {
            let _ = fs::remove_file(&tmp);
            return Err(cannot_write(
                path,
                existed.is_some(),
                &io::Error::other("could not lock the temporary file"),
            ));
        }
        let out = Output {
            target,
            shown: path.to_path_buf(),
            tmp,
            existed,
            committed: false,
        };
        let w = Sticky {
            inner: BufWriter::new(file),
            error: None,
            pos: 0,
        };
        Ok((out, w))
    }

    /// Flush, sync and move the finished file into place.
    pub fn commit(mut self, mut w: Sticky) -> Result<()> {
        let fail = |e: &io::Error| cannot_write(&self.shown, self.existed.is_some(), e);
        if let Err(e) = w.inner.flush() {
            w.fail(e);
        }
        if let Some(e) = &w.error {
            return Err(fail(e));
        }
        let file = w.inner.into_inner().map_err(|e| fail(e.error()))?;
        file.sync_all().map_err(|e| fail(&e))?;
        drop(file);
        if let Some(p) = &self.existed {
            // The replacement keeps the old file's permissions.
            let _ = fs::set_permissions(&self.tmp, p.clone());
        }
        fs::rename(&self.tmp, &self.target).map_err(|e| fail(&e))?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for Output {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_file(&self.tmp);
        }
    }
}

/// One observation segment as `show` prints it: `[a:b]  name  = what (clipped to [lo, hi])`.
pub fn segment_line(s: &envspec::ir::Segment, what: &str) -> String {
    let clip = s
        .clip
        .map(|(lo, hi)| format!("  (clipped to [{lo}, {hi}])"))
        .unwrap_or_default();
    format!(
        "[{}:{}]  {}  = {what}{clip}",
        s.offset,
        s.offset + s.len(),
        s.name
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp_dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("envc-output-{tag}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&d);
        fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn replaces_whole_or_not_at_all() {
        let d = tmp_dir("replace");
        let p = d.join("t.npz");
        fs::write(&p, b"old").unwrap();
        // Abandoned half-way: the old file stays, no temporary is left.
        let (out, mut w) = Output::create(&p).unwrap();
        w.write_all(b"partial").unwrap();
        drop(out);
        drop(w);
        assert_eq!(fs::read(&p).unwrap(), b"old");
        assert_eq!(fs::read_dir(&d).unwrap().count(), 1);
        let (out, mut w) = Output::create(&p).unwrap();
        w.write_all(b"new").unwrap();
        out.commit(w).unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"new");
        assert_eq!(fs::read_dir(&d).unwrap().count(), 1);
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn a_killed_runs_temporary_is_removed_a_running_ones_is_not() {
        let d = tmp_dir("temps");
        let p = d.join("t.npz");
        let dead = d.join(".t.npz.envc-1-2.tmp");
        fs::write(&dead, b"partial").unwrap();
        let (running, w) = Output::create(&p).unwrap();
        let (out, w2) = Output::create(&p).unwrap();
        assert!(!dead.exists());
        // Both runs' temporaries are there, each held by its own lock.
        assert_eq!(fs::read_dir(&d).unwrap().count(), 2);
        out.commit(w2).unwrap();
        running.commit(w).unwrap();
        assert_eq!(fs::read_dir(&d).unwrap().count(), 1);
        let _ = fs::remove_dir_all(&d);
    }

    #[test]
    fn the_same_file_by_any_name_is_refused() {
        let d = tmp_dir("same");
        let a = d.join("a.npy");
        fs::write(&a, b"x").unwrap();
        fs::hard_link(&a, d.join("hard.npy")).unwrap();
        std::os::unix::fs::symlink(&a, d.join("soft.npy")).unwrap();
        for out in ["a.npy", "hard.npy", "soft.npy"] {
            let e = refuse_input(&d.join(out), &[("--actions", &a)]).unwrap_err();
            assert!(e.to_string().starts_with("error[E1411]"), "{e}");
        }
        refuse_input(&d.join("other.npz"), &[("--actions", &a)]).unwrap();
        let _ = fs::remove_dir_all(&d);
    }
}
