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

#[cfg(test)]
mod tests {
    use super::*;
    use ndarray::{Array2, IxDyn, arr1};

    fn rows(n: usize) -> ArrayD<f32> {
        Array2::from_shape_fn((n, 2), |(i, j)| (i * 2 + j) as f32).into_dyn()
    }

    #[test]
    fn head_keeps_the_first_rows_and_the_element_type_in_arrays_and_dicts() {
        let t = Tensor::F32(rows(4));
        let h = t.head(2);
        assert_eq!(h.shape(), &[2, 2]);
        assert_eq!(h.dtype(), Some(Dtype::F32));
        assert_eq!(
            h.as_f32().unwrap().as_slice().unwrap(),
            &[0.0, 1.0, 2.0, 3.0]
        );
        let d = Data::Dict(vec![
            ("a".into(), Data::Tensor(t.clone())),
            (
                "b".into(),
                Data::Tensor(Tensor::Bool(arr1(&[true, false, true, true]).into_dyn())),
            ),
        ]);
        assert_eq!(d.rows(), 4);
        let dh = d.head(3);
        assert_eq!(dh.rows(), 3);
        assert_eq!(
            dh.get("b").and_then(Data::tensor).map(Tensor::rows),
            Some(3)
        );
        assert!(dh.get("c").is_none() && dh.tensor().is_none());
    }

    #[test]
    fn uint64_has_no_dtype_and_bools_widen_to_zero_and_one() {
        let u = Tensor::U64(ArrayD::from_elem(IxDyn(&[3]), 7u64));
        assert_eq!((u.dtype(), u.dtype_name()), (None, "uint64"));
        let b = Tensor::Bool(arr1(&[true, false]).into_dyn());
        assert_eq!(b.to_f64().as_slice().unwrap(), &[1.0, 0.0]);
        assert_eq!(b.dtype_name(), "bool");
        assert!(b.as_f64().is_none() && b.as_bool().is_some());
        assert_eq!(Tensor::F64(ArrayD::zeros(IxDyn(&[0]))).rows(), 0);
    }

    #[test]
    fn an_episode_is_as_long_as_its_flags_and_returns_its_rewards_in_any_type() {
        let ep = Episode {
            id: 0,
            seed: Some(1),
            observations: Data::Tensor(Tensor::F64(ArrayD::zeros(IxDyn(&[4, 1])))),
            actions: Data::Tensor(Tensor::F32(rows(3))),
            rewards: Tensor::I64(arr1(&[1i64, -2, 5]).into_dyn()),
            terminations: arr1(&[false, false, true]),
            truncations: arr1(&[false, false, false]),
            infos: vec![(
                "success".into(),
                Data::Tensor(Tensor::F64(ArrayD::zeros(IxDyn(&[4])))),
            )],
        };
        assert_eq!((ep.len(), ep.is_empty()), (3, false));
        assert_eq!(ep.episode_return(), 4.0);
        assert!(ep.info("success").is_some() && ep.info("missing").is_none());
    }
}
