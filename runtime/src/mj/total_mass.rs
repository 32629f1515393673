//! `<compiler settotalmass>` done by envc, not by MuJoCo's compiler: MuJoCo 3.17 deprecates the
//! attribute (it is announced for removal), and Gymnasium's HalfCheetah needs it. The spec's
//! value is taken off before compiling and applied to the compiled model as MuJoCo's compiler
//! applies it (`mj_setTotalmass`, then the model's constants again), so the model is the one
//! MuJoCo makes, bit for bit (`mujoco_catch`'s tests compare every bundled model).

use mujoco_rs::prelude::*;

use crate::mj::calls::{Call, call};

/// A total mass taken off a spec, with the `<statistic>` values the spec sets (NaN where it sets
/// none), read before compiling: the compiler writes its own into the spec.
pub(crate) struct Taken {
    total: f64,
    stat: [f64; 7],
}

fn stat_values(s: &mujoco_rs::mujoco_c::mjStatistic) -> [f64; 7] {
    let c = s.center;
    [
        s.extent,
        s.meaninertia,
        s.meanmass,
        s.meansize,
        c[0],
        c[1],
        c[2],
    ]
}

/// Take the spec's total mass off its compiler options, so MuJoCo's compiler does not apply it;
/// `None` when it sets none. [`restore`] puts it back.
pub(crate) fn take(spec: &mut MjSpec) -> Option<Taken> {
    let total = spec.compiler().settotalmass();
    if total <= 0.0 {
        return None;
    }
    spec.compiler_mut().set_settotalmass(-1.0);
    Some(Taken {
        total,
        stat: stat_values(&spec.ffi().stat),
    })
}

/// The spec as it was parsed (a spec may be compiled again).
pub(crate) fn restore(spec: &mut MjSpec, taken: &Taken) {
    spec.compiler_mut().set_settotalmass(taken.total);
    let s = crate::mj::stat::of_spec(spec);
    let v = taken.stat;
    (s.extent, s.meaninertia, s.meanmass, s.meansize) = (v[0], v[1], v[2], v[3]);
    s.center = [v[4], v[5], v[6]];
}

/// Scale every body's mass and inertia so the masses sum to `total`, as `mj_setTotalmass` does
/// (one factor, `max(mjMINVAL, total / max(mjMINVAL, Σ mass))`, the world body left alone), then
/// recompute what MuJoCo's compiler derives from the masses (`mj_setConst`, as the compiler runs
/// it after scaling): position actuators' `dampratio` are put back first (the compile turned
/// them into a damping of the unscaled masses), and the spec's own `<statistic>` values after.
pub(crate) fn apply(spec: &MjSpec, model: &mut MjModel, taken: &Taken) -> Result<(), String> {
    const MJMINVAL: f64 = 1e-15;
    let total = taken.total;
    let sum: f64 = model.body_mass()[1..].iter().sum();
    let scale = MJMINVAL.max(total / MJMINVAL.max(sum));
    for m in &mut model.body_mass_mut()[1..] {
        *m *= scale;
    }
    for i in &mut model.body_inertia_mut()[1..] {
        for x in i.iter_mut() {
            *x *= scale;
        }
    }
    let ratios: Vec<Option<f64>> = spec
        .actuator_iter()
        .map(|a| Some(a.biasprm()[2]).filter(|d| *d > 0.0))
        .collect();
    for (prm, ratio) in model.actuator_biasprm_mut().iter_mut().zip(ratios) {
        if let Some(r) = ratio {
            prm[2] = r;
        }
    }
    // The compiler's statistics of the scaled masses (mj_setConst leaves `meanmass` and
    // `meaninertia` as they were): the mean body mass, and the mean diagonal of M at qpos0.
    let (mean_mass, mean_inertia) = {
        let mut data = MjData::new(&*model);
        call(&mut data, Call::SetConst)?;
        call(&mut data, Call::ResetData)?;
        call(&mut data, Call::Forward)?;
        let nv = model.ffi().nv as usize;
        let mut full = vec![0.0; nv * nv];
        data.full_m(&mut full).map_err(|e| e.to_string())?;
        let masses = &model.body_mass()[1..];
        let mean_mass = (!masses.is_empty())
            .then(|| masses.iter().fold(0.0, |a, m| a + m) / masses.len() as f64);
        let mean_inertia =
            (nv > 0).then(|| (0..nv).fold(0.0, |a, i| a + full[i * nv + i]) / nv as f64);
        (mean_mass, mean_inertia)
    };
    {
        let m = crate::mj::stat::of_model(model);
        m.meanmass = mean_mass.unwrap_or(m.meanmass);
        m.meaninertia = mean_inertia.unwrap_or(m.meaninertia);
    }
    // The spec's own `<statistic>` values win, as in the compiler.
    let v = taken.stat;
    let m = crate::mj::stat::of_model(model);
    for (mine, user) in [
        (&mut m.extent, v[0]),
        (&mut m.meaninertia, v[1]),
        (&mut m.meanmass, v[2]),
        (&mut m.meansize, v[3]),
    ] {
        if !user.is_nan() {
            *mine = user;
        }
    }
    if !v[4].is_nan() {
        m.center = [v[4], v[5], v[6]];
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use std::path::{Path, PathBuf};

    use mujoco_rs::prelude::*;

    use crate::mj::catch::{compile, parse};

    /// Every bundled model that declares `settotalmass`.
    fn models() -> Vec<PathBuf> {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets");
        let mut out = vec![];
        let mut dirs = vec![root];
        while let Some(d) = dirs.pop() {
            for e in std::fs::read_dir(&d).unwrap() {
                let p = e.unwrap().path();
                if p.is_dir() {
                    dirs.push(p);
                } else if p.extension().is_some_and(|x| x == "xml")
                    && std::fs::read_to_string(&p)
                        .unwrap()
                        .contains("settotalmass=")
                {
                    out.push(p);
                }
            }
        }
        out.sort();
        out
    }

    fn bits(v: impl IntoIterator<Item = f64>) -> Vec<u64> {
        v.into_iter().map(f64::to_bits).collect()
    }

    /// envc's rescale gives MuJoCo's own compiled masses, inertias and whole model, bit for
    /// bit, for HalfCheetah and every other bundled model that uses the attribute; without it
    /// the masses would differ (the compiler no longer applies the attribute for envc).
    #[test]
    fn envc_rescales_masses_and_inertias_exactly_as_mujoco_does() {
        let files = models();
        let names: Vec<_> = files
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert!(
            names.contains(&"half_cheetah.xml".to_string())
                && names.contains(&"coupled_half_cheetah.xml".to_string()),
            "{names:?}"
        );
        for p in &files {
            let reference = MjModel::from_xml(p).unwrap();
            let mut spec = parse(p).unwrap();
            let ours = compile(&mut spec).unwrap();
            // The spec is left as parsed.
            assert!(spec.compiler().settotalmass() > 0.0);
            let mass = |m: &MjModel| bits(m.body_mass().iter().copied());
            let inertia = |m: &MjModel| bits(m.body_inertia().iter().flatten().copied());
            assert_eq!(mass(&ours), mass(&reference), "{}", p.display());
            assert_eq!(inertia(&ours), inertia(&reference), "{}", p.display());
            let mjb = |m: &MjModel| {
                let mut b = vec![0u8; m.size()];
                m.save_to_buffer(&mut b).unwrap();
                b
            };
            assert!(
                mjb(&ours) == mjb(&reference),
                "{}: mjb differs",
                p.display()
            );

            let mut plain = parse(p).unwrap();
            super::take(&mut plain).unwrap();
            let unscaled = compile(&mut plain).unwrap();
            assert_ne!(mass(&unscaled), mass(&reference), "{}", p.display());
        }
    }
}
