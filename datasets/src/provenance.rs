//! What made a dataset, carried inside it (`envc_provenance` in `metadata.json`, and in the env
//! spec's kwargs when the env is envc's own registration): the spec as it was named (a bundled id
//! or the spec file's absolute path), the text of every file envspec parsed to make it (the spec,
//! a maze's map, the robot spec, the MJCF and its includes) and a hash of every file it read
//! (meshes and textures too), plus the MuJoCo and envc versions.
//!
//! Recovering ([`recover`]) finds the spec at its recorded id or path and checks every file
//! against its hash: equal, it opens as recorded; different, it is refused (E1212) unless the
//! caller accepts the current spec (W1212). When nothing is there any more (the spec moved, another
//! machine), the recorded files are written into a cache directory, laid out as they were, and
//! the env is opened from there; a mesh not carried in the dataset must still be at its recorded
//! place with its recorded hash (E1213 otherwise).

use std::path::{Component, Path, PathBuf};

use envspec::source::{FileRead, fnv1a};
use serde_json::{Map, Value, json};

use crate::error::DatasetError;

/// The layout of the record; a newer one is refused rather than misread.
const FORMAT: u64 = 1;

/// One file of the record.
struct Entry {
    /// Relative to the spec file's directory, `/`-separated (`../../assets/x.xml`).
    rel: String,
    hash: u64,
    text: Option<String>,
}

fn fail(why: impl Into<String>) -> DatasetError {
    DatasetError::Provenance { why: why.into() }
}

/// Canonical where the file exists (as `envc_spec_arg` names a spec file), so the record's
/// relative paths hold from the spec's real directory.
fn absolute(p: &Path) -> PathBuf {
    p.canonicalize().unwrap_or_else(|_| {
        envspec::path::normalize(&std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf()))
    })
}

/// `to` relative to the directory `from`, lexically (both absolute and normalized).
fn relative(from: &Path, to: &Path) -> String {
    let f: Vec<Component> = from.components().collect();
    let t: Vec<Component> = to.components().collect();
    let common = f.iter().zip(&t).take_while(|(a, b)| a == b).count();
    let mut parts: Vec<String> = vec!["..".into(); f.len() - common];
    parts.extend(
        t[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    parts.join("/")
}

fn read_limited(path: &Path) -> Result<Vec<u8>, String> {
    envspec::limits::check_file(path, envspec::limits::MAX_ASSET_BYTES)
        .map_err(|e| e.to_string())?;
    std::fs::read(path).map_err(|e| e.to_string())
}

/// The record of a spec opened from `spec_path` (named `spec_arg`: its bundled id or its
/// absolute path) that read `inputs`. Every file is read again and must hash as it did when the
/// env was made, so the record is of the spec the episodes ran, not of a file edited since.
pub(crate) fn record(
    kind: &str,
    spec_arg: &str,
    spec_path: &Path,
    inputs: &[FileRead],
) -> Result<Value, DatasetError> {
    let spec_abs = absolute(spec_path);
    let dir = spec_abs.parent().unwrap_or(Path::new("/"));
    let mut files = vec![];
    for f in inputs {
        let abs = absolute(&f.path);
        let bytes = read_limited(&abs).map_err(|e| {
            fail(format!(
                "{} (read to make the env) cannot be read again to record it: {e}",
                abs.display()
            ))
        })?;
        let hash = fnv1a(&bytes);
        if f.hash.is_some_and(|h| h != hash) {
            return Err(fail(format!(
                "{} changed after the env was made from it; nothing was published",
                abs.display()
            )));
        }
        let mut e = Map::new();
        e.insert("path".into(), json!(relative(dir, &abs)));
        e.insert("fnv1a64".into(), json!(format!("{hash:016x}")));
        // Files envspec parsed travel whole; meshes and textures (MuJoCo's) by hash only.
        if f.hash.is_some()
            && let Ok(text) = String::from_utf8(bytes)
        {
            e.insert("text".into(), json!(text));
        }
        files.push(Value::Object(e));
    }
    Ok(json!({
        "format": FORMAT,
        "kind": kind,
        "spec": spec_arg,
        "files": files,
        "mujoco_version": envc::mujoco_version(),
        "envc_version": env!("CARGO_PKG_VERSION"),
    }))
}

/// What [`recover`] may do besides the default.
#[derive(Clone, Copy, Debug, Default)]
pub struct RecoverOptions {
    /// Open the spec found at the recorded id or path even if it differs (W1212), instead of E1212.
    pub accept_changed_spec: bool,
    /// Refuse (E1214) a dataset made with another MuJoCo version, instead of W1214.
    pub refuse_other_mujoco: bool,
    /// Open the dataset's own copy of the spec even where a spec is found at the recorded id or
    /// path (a bundled spec an envc upgrade changed, an edited file one keeps).
    pub use_recorded_spec: bool,
}

/// The spec to open for a dataset, and the coded warnings met on the way.
#[derive(Clone, Debug)]
pub struct RecoveredSpec {
    /// A bundled id or a spec file: the recorded one, or the copy written from the record.
    pub target: String,
    /// `warning[W1212]: ...`, `warning[W1214]: ...`.
    pub warnings: Vec<String>,
}

/// The MuJoCo version check: W1214, or E1214 when refused.
pub(crate) fn check_mujoco(
    dataset: &str,
    recorded: Option<&str>,
    opts: RecoverOptions,
    warnings: &mut Vec<String>,
) -> Result<(), DatasetError> {
    let running = envc::mujoco_version();
    match recorded {
        Some(r) if r != running => {
            if opts.refuse_other_mujoco {
                return Err(DatasetError::OtherMujoco {
                    dataset: dataset.into(),
                    recorded: r.into(),
                    running,
                });
            }
            warnings.push(format!(
                "warning[W1214]: dataset `{dataset}` was made with MuJoCo {r}; this process runs \
                 MuJoCo {running}, so replayed episodes may differ from the stored ones"
            ));
        }
        _ => {}
    }
    Ok(())
}

fn entries(record: &Value) -> Result<Vec<Entry>, DatasetError> {
    let format = record.get("format").and_then(Value::as_u64).unwrap_or(0);
    if format != FORMAT {
        return Err(fail(format!(
            "envc_provenance has format {format}; this envc reads format {FORMAT} (a newer envc wrote it?)"
        )));
    }
    let files = record
        .get("files")
        .and_then(Value::as_array)
        .filter(|f| !f.is_empty())
        .ok_or_else(|| fail("envc_provenance lists no files"))?;
    files
        .iter()
        .map(|f| {
            let rel = f.get("path").and_then(Value::as_str);
            let hash = f
                .get("fnv1a64")
                .and_then(Value::as_str)
                .and_then(|h| u64::from_str_radix(h, 16).ok());
            match (rel, hash) {
                (Some(rel), Some(hash)) if !Path::new(rel).is_absolute() => Ok(Entry {
                    rel: rel.into(),
                    hash,
                    text: f.get("text").and_then(Value::as_str).map(String::from),
                }),
                _ => Err(fail(format!(
                    "envc_provenance has a malformed file entry: {f}"
                ))),
            }
        })
        .collect()
}

/// Where the recorded spec is now: its bundled id's file, or the file at its recorded path.
fn locate(spec: &str) -> Option<PathBuf> {
    let p = Path::new(spec);
    if p.is_absolute() || spec.ends_with(".toml") {
        return p.is_file().then(|| p.to_path_buf());
    }
    envspec::registry::lookup(spec).ok().map(|e| e.path.clone())
}

/// Each recorded file that differs at `dir` (the spec's directory now), with how.
fn changes(dir: &Path, files: &[Entry]) -> Vec<String> {
    files
        .iter()
        .filter_map(|e| {
            let p = envspec::path::normalize(&dir.join(&e.rel));
            match read_limited(&p) {
                Ok(b) if fnv1a(&b) == e.hash => None,
                Ok(_) => Some(format!("{} changed", p.display())),
                Err(why) => Some(format!("{} is gone ({why})", p.display())),
            }
        })
        .collect()
}

/// The spec to open for a dataset's record (see the module's documentation).
pub fn recover(
    dataset: &str,
    record: &Value,
    opts: RecoverOptions,
) -> Result<RecoveredSpec, DatasetError> {
    let mut warnings = vec![];
    check_mujoco(
        dataset,
        record.get("mujoco_version").and_then(Value::as_str),
        opts,
        &mut warnings,
    )?;
    let spec = record
        .get("spec")
        .and_then(Value::as_str)
        .ok_or_else(|| fail("envc_provenance names no spec"))?;
    let files = entries(record)?;
    if let Some(path) = locate(spec).filter(|_| !opts.use_recorded_spec) {
        let dir = absolute(&path);
        let dir = dir.parent().unwrap_or(Path::new("/"));
        let changed = changes(dir, &files);
        if !changed.is_empty() {
            if !opts.accept_changed_spec {
                return Err(DatasetError::SpecChanged {
                    dataset: dataset.into(),
                    spec: spec.into(),
                    changes: changed.join("; "),
                });
            }
            warnings.push(format!(
                "warning[W1212]: dataset `{dataset}` was recorded with another version of `{spec}` \
                 ({}); using the current one, so its episodes may not replay",
                changed.join("; ")
            ));
        }
        return Ok(RecoveredSpec {
            target: spec.into(),
            warnings,
        });
    }
    let target = materialize(spec, &files)?;
    Ok(RecoveredSpec {
        target: target.display().to_string(),
        warnings,
    })
}

/// `$XDG_CACHE_HOME/envc/recovered`, `~/.cache/envc/recovered`, else under the temporary directory.
fn cache_dir() -> PathBuf {
    if let Some(x) = std::env::var_os("XDG_CACHE_HOME").filter(|x| !x.is_empty()) {
        return PathBuf::from(x).join("envc").join("recovered");
    }
    if let Some(h) = std::env::var_os("HOME").filter(|h| !h.is_empty()) {
        return PathBuf::from(h).join(".cache/envc/recovered");
    }
    std::env::temp_dir().join("envc-recovered")
}

/// The spec's place inside a copy: one level per `..` the deepest file climbs, so every file
/// stays inside the copy.
fn spec_place(spec: &str, files: &[Entry]) -> PathBuf {
    let up = files
        .iter()
        .map(|e| {
            Path::new(&e.rel)
                .components()
                .take_while(|c| matches!(c, Component::ParentDir))
                .count()
        })
        .max()
        .unwrap_or(0);
    let mut p: PathBuf = std::iter::repeat_n("d", up).collect();
    let name = Path::new(&files[0].rel)
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_else(|| format!("{spec}.toml").into());
    p.push(name);
    p
}

/// Whether a copy at `root` holds every file of the record with its hash.
fn intact(root: &Path, place: &Path, files: &[Entry]) -> bool {
    let dir = root.join(place);
    let dir = dir.parent().unwrap_or(root);
    changes(dir, files).is_empty()
}

/// Write the recorded files under the cache (a temporary directory renamed into place, so a copy
/// is whole or absent) and return the spec's path in it. A file the record carries by hash only
/// is copied from its recorded place, if it is still there with that hash.
fn materialize(spec: &str, files: &[Entry]) -> Result<PathBuf, DatasetError> {
    let key = files.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, e| {
        fnv1a(format!("{h:x}{}{:x}", e.rel, e.hash).as_bytes())
    });
    let base = cache_dir();
    let root = base.join(format!("{key:016x}"));
    let place = spec_place(spec, files);
    if intact(&root, &place, files) {
        return Ok(root.join(place));
    }
    // Where a file carried by hash only may still be: beside the recorded spec file (a bundled
    // id names no place).
    let old_dir = Some(Path::new(spec))
        .filter(|p| p.is_absolute())
        .and_then(Path::parent)
        .map(Path::to_path_buf);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let tmp = base.join(format!(".tmp-{key:016x}-{}-{nanos}", std::process::id()));
    let write = || -> Result<(), DatasetError> {
        let spec_dir = tmp.join(&place);
        let spec_dir = spec_dir.parent().unwrap_or(&tmp);
        for e in files {
            let dest = envspec::path::normalize(&spec_dir.join(&e.rel));
            if let Some(d) = dest.parent() {
                std::fs::create_dir_all(d).map_err(|er| fail(format!("{}: {er}", d.display())))?;
            }
            let bytes = match (&e.text, &old_dir) {
                (Some(t), _) => t.clone().into_bytes(),
                (None, Some(old)) => {
                    let src = envspec::path::normalize(&old.join(&e.rel));
                    match read_limited(&src) {
                        Ok(b) if fnv1a(&b) == e.hash => b,
                        _ => return Err(not_carried(spec, &e.rel, Some(&src))),
                    }
                }
                (None, None) => return Err(not_carried(spec, &e.rel, None)),
            };
            if fnv1a(&bytes) != e.hash {
                return Err(fail(format!(
                    "the dataset's copy of {} does not match its recorded hash",
                    e.rel
                )));
            }
            std::fs::write(&dest, &bytes)
                .map_err(|er| fail(format!("{}: {er}", dest.display())))?;
        }
        Ok(())
    };
    let written = write();
    if let Err(e) = written {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(e);
    }
    if std::fs::rename(&tmp, &root).is_err() {
        // Another process wrote the same copy first (same key, same bytes), or a damaged one is
        // in the way: keep a whole one.
        if !intact(&root, &place, files) {
            let _ = std::fs::remove_dir_all(&root);
            if let Err(e) = std::fs::rename(&tmp, &root) {
                let _ = std::fs::remove_dir_all(&tmp);
                return Err(fail(format!(
                    "cannot put the copy of the recorded spec `{spec}` at {}: {e}",
                    root.display()
                )));
            }
        }
        let _ = std::fs::remove_dir_all(&tmp);
    }
    Ok(root.join(place))
}

fn not_carried(spec: &str, rel: &str, at: Option<&Path>) -> DatasetError {
    fail(format!(
        "`{spec}` is not where the dataset recorded it, and the dataset carries {rel} by hash only \
         (a mesh or texture){}; put the spec back, or the file beside the recorded spec",
        at.map(|p| format!(", which is not at {} with that hash", p.display()))
            .unwrap_or_default()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths_climb_and_descend() {
        let r = relative(Path::new("/a/specs/g"), Path::new("/a/assets/x.xml"));
        assert_eq!(r, "../../assets/x.xml");
        assert_eq!(relative(Path::new("/a"), Path::new("/a/b.toml")), "b.toml");
    }
}
