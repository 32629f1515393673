//! A policy MLP exported from Stable-Baselines3 to `.npz` (`scripts/train_policy.py`), run without
//! torch: hidden layers (ReLU or tanh), then the action mean `mu`. SAC/TQC actors squash
//! (`tanh`, scaled to the action bounds), PPO clips the mean to them. Stochastic actions add
//! `exp(log_std) * N(0, 1)` before squashing or clipping, the normals drawn from the generator
//! the caller passes (episode k's, in a dataset build).

use std::path::{Path, PathBuf};

use ndarray::{Array1, Array2};
use ndarray_npy::NpzReader;

use crate::error::DatasetError;
use envc::rng::NumpyRng;

/// Bounds SB3 clamps a SAC actor's `log_std` to.
const LOG_STD_MIN: f64 = -20.0;
const LOG_STD_MAX: f64 = 2.0;

#[derive(Clone, Debug)]
struct Layer {
    w: Array2<f32>,
    b: Array1<f32>,
}

impl Layer {
    fn apply(&self, x: &[f64], out: &mut Vec<f64>) {
        out.clear();
        for (row, b) in self.w.outer_iter().zip(self.b.iter()) {
            let mut s = f64::from(*b);
            for (w, v) in row.iter().zip(x) {
                s += f64::from(*w) * v;
            }
            out.push(s);
        }
    }
    fn inputs(&self) -> usize {
        self.w.ncols()
    }
    fn outputs(&self) -> usize {
        self.w.nrows()
    }
}

#[derive(Clone, Debug)]
enum LogStd {
    /// PPO: one learned vector.
    Fixed(Vec<f64>),
    /// SAC / TQC: a linear head on the last hidden layer.
    Head(Layer),
}

/// A loaded `.npz` policy.
#[derive(Clone, Debug)]
pub struct MlpPolicy {
    path: PathBuf,
    hidden: Vec<Layer>,
    tanh: bool,
    squash: bool,
    mu: Layer,
    log_std: LogStd,
    low: Vec<f64>,
    high: Vec<f64>,
    // Scratch buffers: one action costs no allocation.
    a: Vec<f64>,
    b: Vec<f64>,
    mean: Vec<f64>,
    std: Vec<f64>,
}

impl MlpPolicy {
    /// Read `path`; every array is checked (E1802), also against the env's spaces when
    /// [`MlpPolicy::check_spaces`] is called.
    pub fn load(path: &Path) -> Result<MlpPolicy, DatasetError> {
        let bad = |why: String| DatasetError::BadPolicy {
            path: path.to_path_buf(),
            why,
        };
        let file = std::fs::File::open(path).map_err(|e| bad(e.to_string()))?;
        let mut npz = NpzReader::new(file).map_err(|e| bad(format!("not an .npz file ({e})")))?;
        let names = npz.names().map_err(|e| bad(e.to_string()))?;
        let has = |n: &str| names.iter().any(|x| x == n || x == &format!("{n}.npy"));
        let mut mat = |n: &str| -> Result<Array2<f32>, DatasetError> {
            npz.by_name::<ndarray::OwnedRepr<f32>, ndarray::Ix2>(n)
                .map_err(|e| bad(format!("array `{n}`: {e} (expected a 2-D float32 array)")))
        };
        let mut hidden_w = vec![];
        let mut i = 0;
        while has(&format!("hidden_w{i}")) {
            hidden_w.push(mat(&format!("hidden_w{i}"))?);
            i += 1;
        }
        let mu_w = mat("mu_w")?;
        let log_std_w = if has("log_std_w") {
            Some(mat("log_std_w")?)
        } else {
            None
        };
        let mut vec = |n: &str| -> Result<Array1<f32>, DatasetError> {
            npz.by_name::<ndarray::OwnedRepr<f32>, ndarray::Ix1>(n)
                .map_err(|e| bad(format!("array `{n}`: {e} (expected a 1-D float32 array)")))
        };
        let mut hidden = vec![];
        for (i, w) in hidden_w.into_iter().enumerate() {
            hidden.push(Layer {
                w,
                b: vec(&format!("hidden_b{i}"))?,
            });
        }
        let mu = Layer {
            w: mu_w,
            b: vec("mu_b")?,
        };
        let log_std = match log_std_w {
            Some(w) => LogStd::Head(Layer {
                w,
                b: vec("log_std_b")?,
            }),
            None => LogStd::Fixed(vec("log_std")?.iter().map(|x| f64::from(*x)).collect()),
        };
        let low: Vec<f64> = vec("action_low")?.iter().map(|x| f64::from(*x)).collect();
        let high: Vec<f64> = vec("action_high")?.iter().map(|x| f64::from(*x)).collect();
        let mut flag = |n: &str| -> Result<i64, DatasetError> {
            npz.by_name::<ndarray::OwnedRepr<i64>, ndarray::Ix0>(n)
                .map(|a| a.into_scalar())
                .map_err(|e| bad(format!("array `{n}`: {e} (expected an int64 scalar)")))
        };
        let tanh = match flag("activation")? {
            0 => false,
            1 => true,
            k => {
                return Err(bad(format!(
                    "activation = {k}: expected 0 (relu) or 1 (tanh)"
                )));
            }
        };
        let squash = match flag("squash")? {
            0 => false,
            1 => true,
            k => return Err(bad(format!("squash = {k}: expected 0 (clip) or 1 (tanh)"))),
        };
        let p = MlpPolicy {
            path: path.to_path_buf(),
            hidden,
            tanh,
            squash,
            mu,
            log_std,
            low,
            high,
            a: vec![],
            b: vec![],
            mean: vec![],
            std: vec![],
        };
        p.check_shapes().map_err(bad)?;
        Ok(p)
    }

    fn check_shapes(&self) -> Result<(), String> {
        let mut width = self.obs_dim();
        for (i, l) in self.hidden.iter().enumerate() {
            if l.inputs() != width || l.b.len() != l.outputs() {
                return Err(format!(
                    "hidden layer {i} is {}x{} with {} biases after a layer of {width}",
                    l.outputs(),
                    l.inputs(),
                    l.b.len()
                ));
            }
            width = l.outputs();
        }
        let n = self.act_dim();
        let heads: Vec<&Layer> = match &self.log_std {
            LogStd::Head(h) => vec![&self.mu, h],
            LogStd::Fixed(v) if v.len() != n => {
                return Err(format!("log_std has {} entries for {n} actions", v.len()));
            }
            LogStd::Fixed(_) => vec![&self.mu],
        };
        for h in heads {
            if h.inputs() != width || h.outputs() != n || h.b.len() != n {
                return Err(format!(
                    "an output layer is {}x{} with {} biases; expected {n}x{width}",
                    h.outputs(),
                    h.inputs(),
                    h.b.len()
                ));
            }
        }
        if self.low.len() != n || self.high.len() != n {
            return Err(format!("action_low / action_high must have {n} entries"));
        }
        Ok(())
    }

    /// Observation values the network takes.
    pub fn obs_dim(&self) -> usize {
        self.hidden.first().unwrap_or(&self.mu).inputs()
    }
    /// Action values it gives.
    pub fn act_dim(&self) -> usize {
        self.mu.outputs()
    }

    /// The env's spaces must be the ones the policy was trained on (E1802).
    pub fn check_spaces(
        &self,
        obs_dim: usize,
        low: &[f64],
        high: &[f64],
    ) -> Result<(), DatasetError> {
        let f32s = |v: &[f64]| v.iter().map(|x| *x as f32).collect::<Vec<_>>();
        let why = if obs_dim != self.obs_dim() {
            Some(format!(
                "the policy takes {} observation values; the env gives {obs_dim}",
                self.obs_dim()
            ))
        } else if f32s(low) != f32s(&self.low) || f32s(high) != f32s(&self.high) {
            Some(format!(
                "the policy's action bounds {:?}..{:?} are not the env's {low:?}..{high:?}",
                self.low, self.high
            ))
        } else {
            None
        };
        match why {
            Some(why) => Err(DatasetError::BadPolicy {
                path: self.path.clone(),
                why,
            }),
            None => Ok(()),
        }
    }

    /// One action for `obs`: deterministic with `noise` `None`, else sampled with normals from it.
    pub fn act(&mut self, obs: &[f64], noise: Option<&mut NumpyRng>, action: &mut [f32]) {
        let mut x = std::mem::take(&mut self.a);
        let mut y = std::mem::take(&mut self.b);
        x.clear();
        x.extend_from_slice(obs);
        for l in &self.hidden {
            l.apply(&x, &mut y);
            for v in &mut y {
                *v = if self.tanh { v.tanh() } else { v.max(0.0) };
            }
            std::mem::swap(&mut x, &mut y);
        }
        self.mu.apply(&x, &mut self.mean);
        if let Some(rng) = noise {
            match &self.log_std {
                LogStd::Head(h) => {
                    h.apply(&x, &mut self.std);
                    for s in &mut self.std {
                        *s = s.clamp(LOG_STD_MIN, LOG_STD_MAX).exp();
                    }
                }
                LogStd::Fixed(v) => {
                    self.std.clear();
                    self.std.extend(v.iter().map(|s| s.exp()));
                }
            }
            for (m, s) in self.mean.iter_mut().zip(&self.std) {
                *m += s * rng.standard_normal();
            }
        }
        for (i, a) in action.iter_mut().enumerate() {
            let (lo, hi) = (self.low[i], self.high[i]);
            let v = if self.squash {
                lo + 0.5 * (self.mean[i].tanh() + 1.0) * (hi - lo)
            } else {
                self.mean[i].clamp(lo, hi)
            };
            *a = v as f32;
        }
        self.a = x;
        self.b = y;
    }
}
