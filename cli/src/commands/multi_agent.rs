//! `envc rollout` and `envc show` for multi-agent specs (a spec with an `[agents]` table).

use std::fmt::Write;
use std::path::Path;

use anyhow::Result;
use envc::multi_agent::MultiAgentEnv;
use envspec::agents::AgentsSpec;
use ndarray::{Array1, Array2};
use ndarray_npy::NpzWriter;

use crate::Outcome;

/// Global actions [T, act_dim] are mapped to the agents; writes `obs.<agent>` [n+1, dim],
/// `state` `[n+1, state_dim]`, `reward`, `terminated`, `truncated` `[n]`.
pub fn rollout(
    mut env: MultiAgentEnv,
    seed: Option<u64>,
    a: &Array2<f64>,
    out: &Path,
    auto_reset: bool,
) -> Result<Outcome> {
    let t_max = a.dim().0;
    let n_agents = env.num_agents();
    let mut obs: Vec<Vec<f64>> = vec![vec![]; n_agents];
    let mut state: Vec<f64> = vec![];
    let (mut reward, mut terminated, mut truncated) = (vec![], vec![], vec![]);
    let mut reset_at: Vec<i64> = vec![];
    let mut reset_obs: Vec<Vec<f64>> = vec![vec![]; n_agents];
    let mut reset_state: Vec<f64> = vec![];
    let (o, _) = env.reset(seed);
    for (i, x) in o.iter().enumerate() {
        obs[i].extend_from_slice(x);
    }
    state.extend_from_slice(env.state());
    for t in 0..t_max {
        let g = a.row(t).to_vec();
        let s = env
            .step_global(&g)
            .map_err(|e| anyhow::anyhow!("step {t}: {e}"))?;
        for (i, x) in s.obs.iter().enumerate() {
            obs[i].extend_from_slice(x);
        }
        reward.push(s.reward);
        terminated.push(s.terminated);
        truncated.push(s.truncated);
        let done = s.terminated || s.truncated;
        state.extend_from_slice(env.state());
        if done {
            if !auto_reset {
                break;
            }
            if t + 1 < t_max {
                let (o, _) = env.reset(None);
                for (i, x) in o.iter().enumerate() {
                    reset_obs[i].extend_from_slice(x);
                }
                reset_state.extend_from_slice(env.state());
                reset_at.push(t as i64 + 1);
            }
        }
    }
    let n = reward.len();
    let (dest, f) = crate::output::Output::create(out)?;
    let mut npz = NpzWriter::new(f);
    let names: Vec<String> = env
        .possible_agents()
        .iter()
        .map(|s| s.to_string())
        .collect();
    for (i, name) in names.iter().enumerate() {
        let dim = env.spec().agents[i].obs_dim;
        npz.add_array(
            format!("obs.{name}").as_str(),
            &Array2::from_shape_vec((n + 1, dim), std::mem::take(&mut obs[i]))?,
        )?;
        if auto_reset {
            let r = reset_at.len();
            npz.add_array(
                format!("reset_obs.{name}").as_str(),
                &Array2::from_shape_vec((r, dim), std::mem::take(&mut reset_obs[i]))?,
            )?;
        }
    }
    let sd = env.spec().state_dim();
    npz.add_array("state", &Array2::from_shape_vec((n + 1, sd), state)?)?;
    npz.add_array("reward", &Array1::from(reward))?;
    npz.add_array("terminated", &Array1::from(terminated))?;
    npz.add_array("truncated", &Array1::from(truncated))?;
    if auto_reset {
        let r = reset_at.len();
        npz.add_array(
            "reset_state",
            &Array2::from_shape_vec((r, sd), reset_state)?,
        )?;
        npz.add_array("reset_at", &Array1::from(reset_at))?;
    }
    dest.commit(npz.finish()?)?;
    eprintln!(
        "{} ({} agents, conf {}, k {}): {n} steps written to {}",
        env.spec().base.id,
        n_agents,
        env.spec().conf,
        env.spec().k,
        out.display()
    );
    Ok(Outcome::Ok)
}

/// Each agent's actuators (local action order → global index) and its observation layout.
pub fn show(env: &MultiAgentEnv) -> Result<Outcome> {
    let spec = env.spec();
    let mut o = String::new();
    writeln!(
        o,
        "{}  (multi-agent spec {}, over {}: {})",
        spec.id,
        spec.spec_path.display(),
        spec.base.id,
        spec.base.spec_path.display()
    )?;
    if !spec.doc.is_empty() {
        writeln!(o, "  {}", spec.doc)?;
    }
    writeln!(
        o,
        "agent_conf {} (of: {}), agent_obsk {}; state = the {} observation ({} float64)",
        spec.conf,
        spec.confs.join(", "),
        spec.k,
        spec.base.id,
        spec.state_dim()
    )?;
    if !spec.parity.is_empty() {
        writeln!(o, "parity: {}", spec.parity)?;
    }
    for (i, a) in spec.agents.iter().enumerate() {
        let sp = env.action_space(i);
        writeln!(
            o,
            "\n{}: {} actions in [{}, {}], observation {} float64",
            a.name,
            a.actions.len(),
            sp.low.first().copied().unwrap_or(0.0),
            sp.high.first().copied().unwrap_or(0.0),
            a.obs_dim
        )?;
        writeln!(o, "  actions (local → global):")?;
        for (j, ((node, g), act)) in a.nodes.iter().zip(&a.actions).zip(&a.actuators).enumerate() {
            writeln!(o, "    {j:>3}  {node:<20} -> action[{g}]  actuator {act}")?;
        }
        for (d, level) in a.levels.iter().enumerate() {
            writeln!(o, "  depth {d}: [{}]", level.join(", "))?;
        }
        writeln!(o, "  observation:")?;
        for s in &a.observation {
            let line = crate::commands::show::segment_line(s, &s.element_names().join(", "));
            writeln!(o, "    {line}")?;
        }
    }
    print!("{o}");
    Ok(Outcome::Ok)
}

/// `envc check` of a multi-agent spec beyond the conf it opened with: every conf at k = 0, 1, 2
/// resolves (unless the user chose a conf). Returns the first conf's diagnostics.
pub fn check_confs(spec: &AgentsSpec, overrides: &[envc::Override]) -> Vec<envspec::Diagnostic> {
    let user_conf = overrides.iter().any(|o| o.name == "agent_conf");
    let confs: Vec<String> = if user_conf {
        vec![spec.conf.clone()]
    } else {
        spec.confs.clone()
    };
    for c in &confs {
        for k in 0..=2 {
            let mut o: Vec<envc::Override> = overrides
                .iter()
                .filter(|o| o.name != "agent_conf" && o.name != "agent_obsk")
                .cloned()
                .collect();
            o.push(envc::Override::text("agent_conf", c));
            o.push(envc::Override::text("agent_obsk", &k.to_string()));
            if let Err(d) = envspec::agents::load(&spec.spec_path, &o) {
                return d.0;
            }
        }
    }
    vec![]
}
