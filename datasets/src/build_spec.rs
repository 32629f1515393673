//! Dataset specs as the datasets crate takes them: read by envspec (`envspec::dataset_spec`,
//! which owns the format and its E1801 errors), then checked for what only a dataset writer
//! knows, the id as Minari parses it. Errors keep the one-line `path:line:col: why` form.

use std::path::Path;

use envspec::Diagnostic;
pub use envspec::dataset_spec::{
    Budget, DatasetSpec, PolicyMode, RefScores, StorageFormat, bundled, datasets_dir,
};

use crate::Format;
use crate::error::DatasetError;

/// A dataset spec file, or a bundled dataset's id (`mujoco/hopper/simple-v0`), read and checked.
pub fn open_spec(what: &str) -> Result<DatasetSpec, DatasetError> {
    let (path, _) = envspec::dataset_spec::path_of(what);
    let spec = envspec::dataset_spec::open(what).map_err(|d| bad_spec(&path, d))?;
    checked(spec)
}

/// A dataset spec's text, read and checked; `path` locates errors and resolves the policy file.
pub fn parse_spec(path: &Path, text: &str) -> Result<DatasetSpec, DatasetError> {
    let file = envspec::SourceFile::new(path, text.to_string());
    let spec = envspec::dataset_spec::parse(&file).map_err(|d| bad_spec(path, d))?;
    checked(spec)
}

/// The id must be one Minari accepts.
fn checked(spec: DatasetSpec) -> Result<DatasetSpec, DatasetError> {
    if let Err(e) = crate::DatasetId::parse(&spec.dataset_id) {
        let (line, col) = spec
            .dataset_id_at
            .file
            .line_col(spec.dataset_id_at.span.start);
        return Err(DatasetError::BadSpec {
            path: spec.path.clone(),
            line,
            col,
            why: format!("id = {:?}: {e}", spec.dataset_id),
        });
    }
    Ok(spec)
}

/// envspec's diagnostic as E1801's one line; `path` is the file when the problem has no place
/// in it (an unreadable file).
fn bad_spec(path: &Path, d: Diagnostic) -> DatasetError {
    let (path, (line, col)) = match &d.location {
        Some(at) => (at.file.path.clone(), at.file.line_col(at.span.start)),
        None => (path.to_path_buf(), (0, 0)),
    };
    DatasetError::BadSpec {
        path,
        line,
        col,
        why: d.message,
    }
}

impl From<StorageFormat> for Format {
    fn from(f: StorageFormat) -> Format {
        match f {
            StorageFormat::Arrow => Format::Arrow,
            StorageFormat::Hdf5 => Format::Hdf5,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPEC: &str = "[dataset]\nid = \"t/x-v0\"\ntier = \"x\"\nenv = \"Hopper-v5\"\nsteps = 10\nseed = 1\n[policy]\nfile = \"p.npz\"\nmode = \"deterministic\"\n[metadata]\nalgorithm_name = \"a\"\nauthor = []\ndescription = \"d\"\n";

    #[test]
    fn mistakes_are_one_located_line() {
        let both = SPEC.replace("seed = 1\n", "episodes = 2\nseed = 1\n");
        let e = parse_spec(Path::new("d.toml"), &both).unwrap_err();
        assert_eq!(e.code(), "E1801");
        assert_eq!(
            e.to_string(),
            "error[E1801]: d.toml:6:1: give `steps` or `episodes`, not both"
        );
        let typo = SPEC.replace("mode = ", "mood = ");
        let e = parse_spec(Path::new("d.toml"), &typo).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("error[E1801]: d.toml:9:1: unknown field `mood`")
        );
        // The id as Minari parses it, at the id's key.
        let id = SPEC.replace("t/x-v0", "t/x");
        let e = parse_spec(Path::new("d.toml"), &id).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("error[E1801]: d.toml:2:1: id = \"t/x\": "),
            "{e}"
        );
    }

    #[test]
    fn an_unreadable_spec_names_its_file() {
        let e = open_spec("no/such/dir/d.toml").unwrap_err();
        assert_eq!(e.code(), "E1801");
        assert!(
            e.to_string()
                .starts_with("error[E1801]: no/such/dir/d.toml: "),
            "{e}"
        );
        let e = open_spec("mujoco/hopper/none-v0").unwrap_err();
        assert!(
            e.to_string().contains(
                "`mujoco/hopper/none-v0` is neither a dataset spec file nor a bundled dataset id"
            ),
            "{e}"
        );
    }
}
