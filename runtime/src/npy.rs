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
use ndarray_npy::ReadNpyExt;
use ndarray_npy::npy::header::Header;

/// A 2-D `.npy` array as stored.
#[derive(Clone, Debug, PartialEq)]
pub enum Matrix {
    F64(Array2<f64>),
    F32(Array2<f32>),
}

/// Why a `.npy` file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum NpyError {
    #[error("cannot open {}: {source}", path.display())]
    Open {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: expected a 2-D float64 or float32 .npy array [T, width]: {why}", path.display())]
    Format { path: PathBuf, why: String },
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
        File::open(path).map_err(|source| NpyError::Open {
            path: path.to_path_buf(),
            source,
        })
    };
    check_size(path, &mut open()?)?;
    // ndarray-npy checks the header's dtype and shape against the requested type, so a failed
    // float64 read of a float32 file is a clean error and the file is read again as float32.
    // Fortran-order files are copied into C order, so every row is a contiguous slice.
    if let Ok(a) = Array2::<f64>::read_npy(open()?) {
        return Ok(Matrix::F64(a.as_standard_layout().into_owned()));
    }
    Array2::<f32>::read_npy(open()?)
        .map(|a| Matrix::F32(a.as_standard_layout().into_owned()))
        .map_err(|e| NpyError::Format {
            path: path.to_path_buf(),
            why: e.to_string(),
        })
}

/// ndarray-npy allocates the whole array its header describes before reading the data, so a
/// 128-byte file claiming a shape of 10⁹ × 3 would abort the process (the allocation fails). The
/// header's shape is checked first against the bytes a regular file really holds.
fn check_size(path: &Path, file: &mut File) -> Result<(), NpyError> {
    let format = |why: String| NpyError::Format {
        path: path.to_path_buf(),
        why,
    };
    let header = Header::from_reader(file).map_err(|e| format(e.to_string()))?;
    let (Ok(meta), Ok(at)) = (file.metadata(), file.stream_position()) else {
        return Ok(());
    };
    if !meta.is_file() {
        return Ok(());
    }
    let data = meta.len().saturating_sub(at);
    // float32, the smaller of the two element types read.
    let need = header
        .shape
        .iter()
        .try_fold(4u64, |n, &d| n.checked_mul(d as u64));
    match need {
        Some(need) if need <= data => Ok(()),
        _ => Err(format(format!(
            "its header's shape {:?} needs more data than the {data} bytes the file holds",
            header.shape
        ))),
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
            e.contains("shape [999999999, 3] needs more data than the 8 bytes"),
            "{e}"
        );
        std::fs::write(&p, b"not an npy file").unwrap();
        assert!(matches!(read_matrix(&p), Err(NpyError::Format { .. })));
        let _ = std::fs::remove_file(&p);
        assert!(matches!(read_matrix(&p), Err(NpyError::Open { .. })));
    }
}
