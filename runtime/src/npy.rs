//! The one `.npy` reader: action files given to `envc rollout`, `envc collect` and the maze and
//! multi-agent rollouts, read with `ndarray-npy` (no parsing of our own).
//!
//! The rule: a 2-D array `[T, width]` of float64 or float32, in C or Fortran order. Its dtype is
//! kept: a float32 policy's actions are stepped as float32 (see `Env::step_f32`).
//!
//! ```no_run
//! let a = envc::npy::read_matrix("actions.npy".as_ref())?;
//! let (steps, width) = a.dim();
//! let actions = a.into_f64();
//! # Ok::<(), envc::npy::NpyError>(())
//! ```

use std::fs::File;
use std::io::Seek;
use std::path::{Path, PathBuf};

use ndarray::Array2;
use ndarray_npy::npy::header::Header;
use ndarray_npy::{ReadNpyError, ReadNpyExt};

/// A 2-D `.npy` array as stored.
#[derive(Clone, Debug, PartialEq)]
pub enum Matrix {
    /// Stored as float64.
    F64(Array2<f64>),
    /// Stored as float32.
    F32(Array2<f32>),
}

/// Why a `.npy` file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum NpyError {
    // Not `source`: the message already says why, and a source would be printed again after it.
    /// The file could not be opened.
    #[error("error[E1430]: cannot open {}: {error}", path.display())]
    Open {
        /// The file.
        path: PathBuf,
        /// Why it could not be opened.
        error: std::io::Error,
    },
    /// The file is not a 2-D float64 or float32 array.
    #[error("error[E1430]: {}: expected a 2-D float64 or float32 .npy array [T, width]: {why}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        why: String,
    },
    /// The header promises more data than the file holds.
    #[error("error[E1430]: {} is truncated: expected {expected} bytes of data for shape {shape:?} ({descr}), found {found}", path.display())]
    Truncated {
        /// The file.
        path: PathBuf,
        /// The shape its header declares.
        shape: Vec<usize>,
        /// The header's dtype descriptor (`<f8`, `<f4`).
        descr: String,
        /// Bytes of data the shape needs.
        expected: u64,
        /// Bytes of data present.
        found: u64,
    },
}

impl NpyError {
    /// The stable code of every `.npy` problem (docs/errors.md).
    pub fn code(&self) -> envspec::Code {
        envspec::Code::E1430
    }
}

impl Matrix {
    /// `(rows, columns)`.
    pub fn dim(&self) -> (usize, usize) {
        match self {
            Matrix::F64(a) => a.dim(),
            Matrix::F32(a) => a.dim(),
        }
    }
    /// The values as float64 (exact for float32).
    pub fn into_f64(self) -> Array2<f64> {
        match self {
            Matrix::F64(a) => a,
            Matrix::F32(a) => a.mapv(f64::from),
        }
    }
    /// The values as float32 (float64 is rounded to nearest, as numpy's `astype(float32)`).
    pub fn into_f32(self) -> Array2<f32> {
        match self {
            Matrix::F64(a) => a.mapv(|x| x as f32),
            Matrix::F32(a) => a,
        }
    }
}

/// Read a 2-D float64 or float32 `.npy` file.
pub fn read_matrix(path: &Path) -> Result<Matrix, NpyError> {
    let open = || {
        File::open(path).map_err(|error| NpyError::Open {
            path: path.to_path_buf(),
            error,
        })
    };
    // A device or FIFO would block or never end; a regular file is bounded by what a rollout may
    // hold in memory.
    envspec::limits::check_file(path, envspec::limits::MAX_TRAJECTORY_BYTES).map_err(
        |e| match e {
            envspec::limits::ReadError::Io(error) => NpyError::Open {
                path: path.to_path_buf(),
                error,
            },
            e => NpyError::Format {
                path: path.to_path_buf(),
                why: e.to_string(),
            },
        },
    )?;
    check_size(path, &mut open()?)?;
    // ndarray-npy checks the header's dtype and shape against the requested type, so a failed
    // float64 read of a float32 file is a clean error and the file is read again as float32.
    // Fortran-order files are copied into C order, so every row is a contiguous slice.
    let e64 = match Array2::<f64>::read_npy(open()?) {
        Ok(a) => return Ok(Matrix::F64(a.as_standard_layout().into_owned())),
        Err(e) => e,
    };
    // Only a float64 read refused for its dtype is retried as float32: any other failure of a
    // float64 file (truncated, extra bytes) is that file's problem, not a dtype mismatch.
    let e = match e64 {
        ReadNpyError::WrongDescriptor(_) => match Array2::<f32>::read_npy(open()?) {
            Ok(a) => return Ok(Matrix::F32(a.as_standard_layout().into_owned())),
            Err(e) => e,
        },
        e => e,
    };
    Err(NpyError::Format {
        path: path.to_path_buf(),
        why: e.to_string(),
    })
}

/// ndarray-npy allocates the whole array its header describes before reading the data, so a
/// 128-byte file claiming a shape of 10⁹ × 3 would abort the process (the allocation fails). The
/// header's shape is checked first against the bytes the file really holds: a shortfall is
/// `Truncated`, with the sizes. Descriptors other than float32/float64 are left to ndarray-npy,
/// which refuses them.
fn check_size(path: &Path, file: &mut File) -> Result<(), NpyError> {
    let format = |why: String| NpyError::Format {
        path: path.to_path_buf(),
        why,
    };
    let header = Header::from_reader(&mut *file).map_err(|e| format(e.to_string()))?;
    let (Ok(meta), Ok(at)) = (file.metadata(), file.stream_position()) else {
        return Ok(());
    };
    let found = meta.len().saturating_sub(at);
    let descr = header.type_descriptor.to_string();
    let descr = descr.trim_matches('\'');
    let item: u64 = match descr {
        "<f8" | ">f8" | "=f8" | "f8" => 8,
        "<f4" | ">f4" | "=f4" | "f4" => 4,
        _ => return Ok(()),
    };
    let expected = header
        .shape
        .iter()
        .try_fold(item, |n, &d| n.checked_mul(d as u64));
    match expected {
        Some(expected) if expected <= found => Ok(()),
        _ => Err(NpyError::Truncated {
            path: path.to_path_buf(),
            shape: header.shape.clone(),
            descr: descr.to_string(),
            expected: expected.unwrap_or(u64::MAX),
            found,
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::array;

    fn tmp(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("envc-npy-{}-{name}", std::process::id()))
    }

    #[test]
    fn keeps_the_dtype_and_the_values() {
        let p = tmp("f32.npy");
        let a = array![[0.1f32, -2.5], [3.0, 1e-7]];
        ndarray_npy::write_npy(&p, &a).unwrap();
        assert_eq!(read_matrix(&p).unwrap(), Matrix::F32(a.clone()));
        let p64 = tmp("f64.npy");
        let b = array![[0.1f64, -2.5, 7.0]];
        ndarray_npy::write_npy(&p64, &b).unwrap();
        let m = read_matrix(&p64).unwrap();
        assert_eq!(m.dim(), (1, 3));
        assert_eq!(m.into_f32(), array![[0.1f32, -2.5, 7.0]]);
        assert_eq!(read_matrix(&p).unwrap().into_f64()[[0, 0]], 0.1f32 as f64);
        // A Fortran-order file reads into C order (rows are contiguous).
        let c = array![[1.0f64, 2.0, 3.0], [4.0, 5.0, 6.0]];
        let f = c.t().to_owned();
        assert!(!f.is_standard_layout());
        ndarray_npy::write_npy(&p64, &f).unwrap();
        let Matrix::F64(g) = read_matrix(&p64).unwrap() else {
            panic!("dtype changed")
        };
        assert!(g.is_standard_layout());
        assert_eq!(g, array![[1.0, 4.0], [2.0, 5.0], [3.0, 6.0]]);
        let _ = (std::fs::remove_file(p), std::fs::remove_file(p64));
    }

    #[test]
    fn a_truncated_file_is_said_to_be_truncated() {
        // A float64 file cut short is not a dtype problem (it was reported as "incorrect
        // descriptor ('<f8')" after the float32 retry).
        for (name, full) in [
            ("t64.npy", {
                let p = tmp("full64.npy");
                ndarray_npy::write_npy(&p, &Array2::<f64>::zeros((10, 3))).unwrap();
                p
            }),
            ("t32.npy", {
                let p = tmp("full32.npy");
                ndarray_npy::write_npy(&p, &Array2::<f32>::zeros((10, 3))).unwrap();
                p
            }),
        ] {
            let bytes = std::fs::read(&full).unwrap();
            let p = tmp(name);
            std::fs::write(&p, &bytes[..bytes.len() - 7]).unwrap();
            let e = read_matrix(&p).unwrap_err();
            let (item, descr) = if name == "t64.npy" {
                (8, "<f8")
            } else {
                (4, "<f4")
            };
            assert_eq!(
                e.to_string(),
                format!(
                    "error[E1430]: {} is truncated: expected {} bytes of data for shape [10, 3] ({descr}), found {}",
                    p.display(),
                    30 * item,
                    30 * item - 7
                )
            );
            assert_eq!(e.code(), envspec::Code::E1430);
            let _ = (std::fs::remove_file(p), std::fs::remove_file(full));
        }
    }

    #[test]
    fn wrong_rank_dtype_or_file_is_an_error() {
        let p = tmp("i64.npy");
        ndarray_npy::write_npy(&p, &array![[1i64, 2]]).unwrap();
        assert!(matches!(read_matrix(&p), Err(NpyError::Format { .. })));
        ndarray_npy::write_npy(&p, &array![1.0f64, 2.0]).unwrap();
        assert!(matches!(read_matrix(&p), Err(NpyError::Format { .. })));
        // A header claiming far more data than the file holds is refused before anything is
        // allocated for it (it used to abort: "memory allocation of 23999999976 bytes failed").
        let h = "{'descr': '<f8', 'fortran_order': False, 'shape': (999999999, 3), }";
        let h = format!("{h:<117}\n");
        let mut huge = b"\x93NUMPY\x01\x00".to_vec();
        huge.extend((h.len() as u16).to_le_bytes());
        huge.extend(h.as_bytes());
        huge.extend([0u8; 8]);
        std::fs::write(&p, &huge).unwrap();
        let e = read_matrix(&p).unwrap_err().to_string();
        assert!(
            e.contains("is truncated: expected 23999999976 bytes of data for shape [999999999, 3] (<f8), found 8"),
            "{e}"
        );
        std::fs::write(&p, b"not an npy file").unwrap();
        assert!(matches!(read_matrix(&p), Err(NpyError::Format { .. })));
        let _ = std::fs::remove_file(&p);
        assert!(matches!(read_matrix(&p), Err(NpyError::Open { .. })));
    }
}
