//! Typed arrays read from a dataset.

use ndarray::ArrayD;

use crate::space::Dtype;

/// One stored array with its own element type (Minari never casts: rewards are int64 when the env
/// returned Python ints, float64 otherwise).
#[derive(Clone, Debug, PartialEq)]
pub enum Tensor {
    /// A float64 array.
    F64(ArrayD<f64>),
    /// A float32 array.
    F32(ArrayD<f32>),
    /// A int64 array.
    I64(ArrayD<i64>),
    /// A int32 array.
    I32(ArrayD<i32>),
    /// A int16 array.
    I16(ArrayD<i16>),
    /// A int8 array.
    I8(ArrayD<i8>),
    /// A uint8 array.
    U8(ArrayD<u8>),
    /// A uint64 array (no `Dtype` names it).
    U64(ArrayD<u64>),
    /// A bool array.
    Bool(ArrayD<bool>),
}

macro_rules! each {
    ($t:expr, $a:ident => $e:expr) => {
        match $t {
            Tensor::F64($a) => $e,
            Tensor::F32($a) => $e,
            Tensor::I64($a) => $e,
            Tensor::I32($a) => $e,
            Tensor::I16($a) => $e,
            Tensor::I8($a) => $e,
            Tensor::U8($a) => $e,
            Tensor::U64($a) => $e,
            Tensor::Bool($a) => $e,
        }
    };
}

impl Tensor {
    /// The array's shape.
    pub fn shape(&self) -> &[usize] {
        each!(self, a => a.shape())
    }
    /// Number of rows (the leading dimension).
    pub fn rows(&self) -> usize {
        self.shape().first().copied().unwrap_or(0)
    }
    /// The element type (None for uint64, which `Dtype` does not name).
    pub fn dtype(&self) -> Option<Dtype> {
        Some(match self {
            Tensor::F64(_) => Dtype::F64,
            Tensor::F32(_) => Dtype::F32,
            Tensor::I64(_) => Dtype::I64,
            Tensor::I32(_) => Dtype::I32,
            Tensor::I16(_) => Dtype::I16,
            Tensor::I8(_) => Dtype::I8,
            Tensor::U8(_) => Dtype::U8,
            Tensor::Bool(_) => Dtype::Bool,
            Tensor::U64(_) => return None,
        })
    }
    /// numpy's name of the element type.
    pub fn dtype_name(&self) -> &'static str {
        self.dtype().map(Dtype::numpy_name).unwrap_or("uint64")
    }
    /// Every element as f64 (exact for all types but large 64-bit integers); bools give 0 / 1.
    pub fn to_f64(&self) -> ArrayD<f64> {
        match self {
            Tensor::F64(a) => a.clone(),
            Tensor::F32(a) => a.mapv(f64::from),
            Tensor::I64(a) => a.mapv(|x| x as f64),
            Tensor::I32(a) => a.mapv(f64::from),
            Tensor::I16(a) => a.mapv(f64::from),
            Tensor::I8(a) => a.mapv(f64::from),
            Tensor::U8(a) => a.mapv(f64::from),
            Tensor::U64(a) => a.mapv(|x| x as f64),
            Tensor::Bool(a) => a.mapv(|x| x as u8 as f64),
        }
    }
    /// The array, if it is float64.
    pub fn as_f64(&self) -> Option<&ArrayD<f64>> {
        if let Tensor::F64(a) = self {
            Some(a)
        } else {
            None
        }
    }
    /// The array, if it is float32.
    pub fn as_f32(&self) -> Option<&ArrayD<f32>> {
        if let Tensor::F32(a) = self {
            Some(a)
        } else {
            None
        }
    }
    /// The array, if it is bool.
    pub fn as_bool(&self) -> Option<&ArrayD<bool>> {
        if let Tensor::Bool(a) = self {
            Some(a)
        } else {
            None
        }
    }
    /// The first `n` rows.
    pub fn head(&self, n: usize) -> Tensor {
        use ndarray::{Axis, Slice};
        macro_rules! cut {
            ($v:ident, $a:expr) => {
                Tensor::$v($a.slice_axis(Axis(0), Slice::from(..n)).to_owned())
            };
        }
        match self {
            Tensor::F64(a) => cut!(F64, a),
            Tensor::F32(a) => cut!(F32, a),
            Tensor::I64(a) => cut!(I64, a),
            Tensor::I32(a) => cut!(I32, a),
            Tensor::I16(a) => cut!(I16, a),
            Tensor::I8(a) => cut!(I8, a),
            Tensor::U8(a) => cut!(U8, a),
            Tensor::U64(a) => cut!(U64, a),
            Tensor::Bool(a) => cut!(Bool, a),
        }
    }
}

/// An array, or a dict / tuple of them (Dict and Tuple spaces, nested infos).
#[derive(Clone, Debug, PartialEq)]
pub enum Data {
    /// One array.
    Tensor(Tensor),
    /// Keys in stored order.
    Dict(Vec<(String, Data)>),
}

impl Data {
    /// The array, if this is one.
    pub fn tensor(&self) -> Option<&Tensor> {
        if let Data::Tensor(t) = self {
            Some(t)
        } else {
            None
        }
    }
    /// The entry `key` of a dict (None for an array or a missing key).
    pub fn get(&self, key: &str) -> Option<&Data> {
        match self {
            Data::Dict(items) => items.iter().find(|(k, _)| k == key).map(|(_, d)| d),
            Data::Tensor(_) => None,
        }
    }
    /// Number of rows (a dict's: its first entry's).
    pub fn rows(&self) -> usize {
        match self {
            Data::Tensor(t) => t.rows(),
            Data::Dict(items) => items.first().map(|(_, d)| d.rows()).unwrap_or(0),
        }
    }
    pub(crate) fn head(&self, n: usize) -> Data {
        match self {
            Data::Tensor(t) => Data::Tensor(t.head(n)),
            Data::Dict(items) => {
                Data::Dict(items.iter().map(|(k, d)| (k.clone(), d.head(n))).collect())
            }
        }
    }
}

/// One episode as read back: `observations` and `infos` have T+1 rows, the rest T.
#[derive(Clone, Debug)]
pub struct Episode {
    /// The episode index.
    pub id: u64,
    /// The reset seed, if the writer stored one.
    pub seed: Option<u64>,
    /// Observations, T+1 rows.
    pub observations: Data,
    /// Actions, T rows.
    pub actions: Data,
    /// Rewards, T rows, in the type the env returned.
    pub rewards: Tensor,
    /// Terminated flags, T rows.
    pub terminations: ndarray::Array1<bool>,
    /// Truncated flags, T rows.
    pub truncations: ndarray::Array1<bool>,
    /// Info keys in stored order (T+1 rows each; row 0 is the reset info).
    pub infos: Vec<(String, Data)>,
}

impl Episode {
    /// T, the number of steps.
    pub fn len(&self) -> usize {
        self.terminations.len()
    }
    /// Whether the episode has no steps.
    pub fn is_empty(&self) -> bool {
        self.terminations.is_empty()
    }
    /// The info key `key`, if stored.
    pub fn info(&self, key: &str) -> Option<&Data> {
        self.infos.iter().find(|(k, _)| k == key).map(|(_, d)| d)
    }
    /// Sum of rewards.
    pub fn episode_return(&self) -> f64 {
        self.rewards.to_f64().sum()
    }
}
