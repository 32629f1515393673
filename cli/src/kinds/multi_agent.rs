//! `envc rollout` and `envc show` for multi-agent specs (a spec with an `[agents]` table).

use std::fmt::Write;

use anyhow::Result;
use envc::multi_agent::MultiAgentEnv;
use envspec::multi_agent::MultiAgentSpec;
use ndarray::{Array1, Array2};
use ndarray_npy::NpzWriter;

use crate::Outcome;
use crate::output::Sticky;
use crate::trajectory::Trajectory;

/// A multi-agent trajectory (global actions [T, act_dim] go to the agents): `obs.<agent>`
/// [n+1, dim], `state` `[n+1, state_dim]`; with `--auto-reset` `reset_obs.<agent>`,
/// `reset_state` and `reset_at` of the resets after the first.
pub struct MultiAgentTrajectory {
    obs: Vec<Vec<f64>>,
    state: Vec<f64>,
    reset_at: Vec<i64>,
    reset_obs: Vec<Vec<f64>>,
    reset_state: Vec<f64>,
}

impl MultiAgentTrajectory {
    pub fn new(env: &MultiAgentEnv) -> Self {
        let n_agents = env.num_agents();
        MultiAgentTrajectory {
            obs: vec![vec![]; n_agents],
            state: vec![],
            reset_at: vec![],
            reset_obs: vec![vec![]; n_agents],
            reset_state: vec![],
        }
    }
}

impl Trajectory for MultiAgentTrajectory {
    type Env = MultiAgentEnv;
    fn reset(&mut self, env: &MultiAgentEnv, at: Option<usize>) {
        match at {
            None => {
                for (i, x) in env.observations().iter().enumerate() {
                    self.obs[i].extend_from_slice(x);
                }
                self.state.extend_from_slice(env.state());
            }
            Some(t) => {
                for (i, x) in env.observations().iter().enumerate() {
                    self.reset_obs[i].extend_from_slice(x);
                }
                self.reset_state.extend_from_slice(env.state());
                self.reset_at.push(t as i64);
            }
        }
    }
    fn step(&mut self, env: &MultiAgentEnv) {
        for (i, x) in env.observations().iter().enumerate() {
            self.obs[i].extend_from_slice(x);
        }
        self.state.extend_from_slice(env.state());
    }
    fn write_obs(
        &mut self,
        npz: &mut NpzWriter<Sticky>,
        env: &MultiAgentEnv,
        n: usize,
        auto_reset: bool,
    ) -> Result<()> {
        for (i, name) in env.possible_agents().iter().enumerate() {
            let dim = env.spec().agents[i].obs_dim;
            npz.add_array(
                format!("obs.{name}").as_str(),
                &Array2::from_shape_vec((n + 1, dim), std::mem::take(&mut self.obs[i]))?,
            )?;
            if auto_reset {
                let r = self.reset_at.len();
                npz.add_array(
                    format!("reset_obs.{name}").as_str(),
                    &Array2::from_shape_vec((r, dim), std::mem::take(&mut self.reset_obs[i]))?,
                )?;
            }
        }
        let sd = env.spec().state_dim();
        let state = std::mem::take(&mut self.state);
        npz.add_array("state", &Array2::from_shape_vec((n + 1, sd), state)?)?;
        Ok(())
    }
    fn write_rest(
        self,
        npz: &mut NpzWriter<Sticky>,
        env: &MultiAgentEnv,
        auto_reset: bool,
    ) -> Result<()> {
        if auto_reset {
            let (r, sd) = (self.reset_at.len(), env.spec().state_dim());
            npz.add_array(
                "reset_state",
                &Array2::from_shape_vec((r, sd), self.reset_state)?,
            )?;
            npz.add_array("reset_at", &Array1::from(self.reset_at))?;
        }
        Ok(())
    }
    fn describe(&self, env: &MultiAgentEnv) -> String {
        let s = env.spec();
        format!(
            "{} ({} agents, conf {}, k {})",
            s.base.id,
            env.num_agents(),
            s.conf,
            s.k
        )
    }
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
            let line = crate::output::segment_line(s, &s.element_names().join(", "));
            writeln!(o, "    {line}")?;
        }
    }
    print!("{o}");
    Ok(Outcome::Ok)
}

/// `envc check` of a multi-agent spec beyond the conf it opened with: every conf at k = 0, 1, 2
/// resolves (unless the user chose a conf). Returns the first conf's diagnostics.
pub fn check_confs(
    spec: &MultiAgentSpec,
    overrides: &[envc::Override],
) -> Vec<envspec::Diagnostic> {
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
            if let Err(d) = envspec::multi_agent::load(&spec.spec_path, &o) {
                return d.0;
            }
        }
    }
    vec![]
}
