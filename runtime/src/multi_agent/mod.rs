//! Multi-agent envs (MaMuJoCo v1 semantics, PettingZoo's parallel API): one single-agent env whose
//! actuators are split among agents by a factorization (`[agents]`, see `envspec::multi_agent`).
//!
//! ```no_run
//! use envc::multi_agent::MultiAgentEnv;
//! use envc::Override;
//! let mut env = MultiAgentEnv::from_spec_file(
//!     "specs/mamujoco/ant.toml",
//!     &[Override::text("agent_conf", "2x4"), Override::text("agent_obsk", "1")],
//! )?;
//! let (obs, _info) = env.reset(Some(0));
//! assert_eq!(obs[0].len(), 63);
//! let step = env.step(&[&[0.0; 4], &[0.0; 4]])?;
//! println!("{} {}", step.reward, step.truncated);
//! # Ok::<(), envc::EnvError>(())
//! ```

use std::path::Path;
use std::sync::Arc;

use envspec::multi_agent::MultiAgentSpec;
use envspec::{Override, ResolvedSpec};

use crate::env::{BoxSpace, Env, Info};
use crate::error::EnvError;

mod joint;

/// The result of one multi-agent step. Reward, terminated, truncated and info are shared by every
/// agent (MaMuJoCo gives each agent the same values).
pub struct MultiStep<'a> {
    /// One observation per possible agent, in agent order.
    pub obs: &'a [Vec<f64>],
    /// The task's reward.
    pub reward: f64,
    /// Whether the task's episode ended in a terminal state.
    pub terminated: bool,
    /// Whether the time limit cut the episode short.
    pub truncated: bool,
    /// The task's info dict.
    pub info: Info<'a>,
}

/// Why local observations cannot be mapped back to the state.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MappingError {
    /// The observations do not match the agents in number or length.
    #[error("wrong number of agents or observation length")]
    Shape,
    /// An agent observes a value that is not part of the state.
    #[error("some agent observes values that are not in the state")]
    NoMapping,
    /// This state entry is observed by no agent, so it cannot be recovered.
    #[error("state[{0}] is observed by no agent")]
    Undefined(usize),
    /// Two agents' observations give this state entry different values.
    #[error("two observations disagree about state[{0}]")]
    Conflict(usize),
}

/// A multi-agent env over one simulation.
pub struct MultiAgentEnv {
    spec: Arc<MultiAgentSpec>,
    env: Env,
    obs: Vec<Vec<f64>>,
    action: Vec<f64>,
    live: bool,
    /// Reward, terminated, truncated of the last step.
    last: (f64, bool, bool),
    observation_spaces: Vec<BoxSpace>,
    action_spaces: Vec<BoxSpace>,
}

impl MultiAgentEnv {
    /// Load a multi-agent spec (`agent_conf`, `agent_obsk` and any base parameter can be overridden).
    pub fn from_spec_file(
        path: impl AsRef<Path>,
        overrides: &[Override],
    ) -> Result<MultiAgentEnv, EnvError> {
        let spec = envspec::multi_agent::load(path.as_ref(), overrides)?;
        MultiAgentEnv::new(Arc::new(spec))
    }

    /// Build the env of a resolved multi-agent spec.
    pub fn new(spec: Arc<MultiAgentSpec>) -> Result<MultiAgentEnv, EnvError> {
        let mut base: ResolvedSpec = spec.base.clone();
        // Gymnasium runs mj_rnePostConstraint after every step; envc only when something reads
        // the contact forces, which the agents may do even when the single-agent obs does not.
        base.needs_rne_post_constraint |= spec.reads_contact_forces();
        let mut env = Env::new(Arc::new(base))?;
        env.read_also(spec.sources());
        let space = env.action_space();
        let bound = |b: &[f64], i: usize| {
            if spec.first_element_bounds {
                b[0]
            } else {
                b[i]
            }
        };
        let action_spaces = spec
            .agents
            .iter()
            .map(|a| BoxSpace {
                low: a.actions.iter().map(|&i| bound(&space.low, i)).collect(),
                high: a.actions.iter().map(|&i| bound(&space.high, i)).collect(),
            })
            .collect();
        let observation_spaces = spec
            .agents
            .iter()
            .map(|a| BoxSpace {
                low: vec![f64::NEG_INFINITY; a.obs_dim],
                high: vec![f64::INFINITY; a.obs_dim],
            })
            .collect();
        let obs = spec.agents.iter().map(|a| vec![0.0; a.obs_dim]).collect();
        let action = vec![0.0; spec.act_dim()];
        let mut me = MultiAgentEnv {
            spec,
            env,
            obs,
            action,
            live: false,
            last: (0.0, false, false),
            observation_spaces,
            action_spaces,
        };
        me.write_obs();
        Ok(me)
    }

    /// The resolved multi-agent spec.
    pub fn spec(&self) -> &Arc<MultiAgentSpec> {
        &self.spec
    }
    /// The numerics profile the underlying env computes under.
    pub fn numerics(&self) -> crate::numerics::Profile {
        self.env.numerics()
    }
    /// Compute as the reference does under `profile` (see `Env::set_numerics`).
    pub fn set_numerics(&mut self, profile: crate::numerics::Profile) {
        self.env.set_numerics(profile);
    }
    /// After a failure: `step` refuses (E1103) until the next `reset`.
    pub fn require_reset(&mut self) {
        self.env.require_reset();
    }
    /// The single-agent env underneath.
    pub fn env(&self) -> &Env {
        &self.env
    }
    /// The single-agent env, for settings and rendering (stepping it directly would bypass the
    /// agents' observations).
    pub(crate) fn env_mut(&mut self) -> &mut Env {
        &mut self.env
    }
    /// Render the whole robot (MaMuJoCo renders its single-agent env).
    pub fn render(
        &mut self,
        mode: crate::render::RenderMode,
    ) -> Result<crate::render::Frame<'_>, crate::EnvError> {
        self.env.render(mode)
    }
    /// Colour each agent's limbs (the geoms of the bodies its actuators' joints move) in its own
    /// colour in later frames, or restore the model's colours. A picture of the factorization;
    /// MaMuJoCo itself draws the robot in its model colours (the default).
    pub fn color_agents(&mut self, on: bool) {
        if !on {
            self.env.set_render_tint(vec![]);
            return;
        }
        // Tableau's first colours: distinct for the usual 2 to 8 agents.
        const PALETTE: [[f32; 4]; 8] = [
            [0.12, 0.47, 0.71, 1.0],
            [1.0, 0.5, 0.05, 1.0],
            [0.17, 0.63, 0.17, 1.0],
            [0.84, 0.15, 0.16, 1.0],
            [0.58, 0.4, 0.74, 1.0],
            [0.55, 0.34, 0.29, 1.0],
            [0.89, 0.47, 0.76, 1.0],
            [0.74, 0.74, 0.13, 1.0],
        ];
        let m = self.env.model().ffi();
        let count = |n: i64| usize::try_from(n).unwrap_or(0);
        let nbody = count(m.nbody);
        let model = self.env.model();
        let (geom_body, trn_type, trn_id, jnt_body) = (
            model.geom_bodyid(),
            model.actuator_trntype(),
            model.actuator_trnid().as_flattened(),
            model.jnt_bodyid(),
        );
        let mut body_color = vec![None; nbody];
        for (k, agent) in self.spec.agents.iter().enumerate() {
            for &a in &agent.actions {
                let joint = trn_type.get(a) == Some(&mujoco_rs::mujoco_c::mjtTrn::mjTRN_JOINT);
                if let Some(b) = trn_id
                    .get(2 * a)
                    .filter(|_| joint)
                    .and_then(|&j| jnt_body.get(count(j as i64)))
                    .and_then(|&b| body_color.get_mut(count(b as i64)))
                {
                    *b = Some(PALETTE[k % PALETTE.len()]);
                }
            }
        }
        let tint = geom_body
            .iter()
            .map(|&b| body_color.get(count(b as i64)).copied().flatten())
            .collect();
        self.env.set_render_tint(tint);
    }
    /// Every agent's name (`agent_0`, ...), in order.
    pub fn possible_agents(&self) -> Vec<&str> {
        self.spec.agents.iter().map(|a| a.name.as_str()).collect()
    }
    /// The agents still acting: all after `reset`, none once the episode has ended.
    pub fn agents(&self) -> Vec<&str> {
        if self.live {
            self.possible_agents()
        } else {
            vec![]
        }
    }
    /// The number of agents in the chosen `agent_conf`.
    pub fn num_agents(&self) -> usize {
        self.spec.agents.len()
    }
    /// Agent `agent`'s observation space (panics past `num_agents`).
    pub fn observation_space(&self, agent: usize) -> &BoxSpace {
        &self.observation_spaces[agent]
    }
    /// Each local action's bounds: its actuator's, or (`action_bounds = "first_element"`, MaMuJoCo
    /// v1) the single-agent action space's element 0 for every entry.
    pub fn action_space(&self, agent: usize) -> &BoxSpace {
        &self.action_spaces[agent]
    }
    /// The global state: the single-agent observation.
    pub fn state(&self) -> &[f64] {
        self.env.obs()
    }
    /// The current local observations.
    pub fn observations(&self) -> &[Vec<f64>] {
        &self.obs
    }

    /// Reset the task (seeded as the single-agent env is) and return every agent's observation.
    pub fn reset(&mut self, seed: Option<u64>) -> (&[Vec<f64>], Info<'_>) {
        self.env.reset(seed);
        self.write_obs();
        self.live = true;
        (&self.obs, self.env.reset_info())
    }

    /// Step with one action per agent, in agent order.
    pub fn step(&mut self, actions: &[&[f64]]) -> Result<MultiStep<'_>, EnvError> {
        scatter_local_actions(&self.spec, actions, &mut self.action)?;
        let action = std::mem::take(&mut self.action);
        let r = self.step_global_inner(&action);
        self.action = action;
        r?;
        Ok(self.last_step())
    }

    /// Step with the global action (the single-agent action vector).
    pub fn step_global(&mut self, action: &[f64]) -> Result<MultiStep<'_>, EnvError> {
        self.step_global_inner(action)?;
        Ok(self.last_step())
    }

    /// `step_global` with a float32 action: costs computed from the action are float32, as numpy
    /// computes them (see `Env::step_f32`). MaMuJoCo's single-agent mode (`agent_conf = "none"`)
    /// hands the agent's action to the task as given, so a float32 policy steps this way there.
    pub fn step_global_f32(&mut self, action: &[f32]) -> Result<MultiStep<'_>, EnvError> {
        let s = self.env.step_f32(action)?;
        let last = (s.reward, s.terminated, s.truncated);
        self.finish_step(last);
        Ok(self.last_step())
    }

    fn step_global_inner(&mut self, action: &[f64]) -> Result<(), EnvError> {
        let s = self.env.step(action)?;
        let last = (s.reward, s.terminated, s.truncated);
        self.finish_step(last);
        Ok(())
    }

    fn finish_step(&mut self, (reward, term, trunc): (f64, bool, bool)) {
        self.last = (reward, term, trunc);
        self.write_obs();
        if term || trunc {
            self.live = false;
        }
    }

    fn last_step(&self) -> MultiStep<'_> {
        MultiStep {
            obs: &self.obs,
            reward: self.last.0,
            terminated: self.last.1,
            truncated: self.last.2,
            info: self.env.step_info(),
        }
    }

    /// `map_local_actions_to_global_action`.
    pub fn local_actions_to_global(&self, actions: &[&[f64]]) -> Result<Vec<f64>, EnvError> {
        let mut g = vec![f64::NAN; self.spec.act_dim()];
        scatter_local_actions(&self.spec, actions, &mut g)?;
        Ok(g)
    }

    /// `map_global_action_to_local_actions`: one vector per agent, in the agent's action order.
    pub fn global_action_to_local(&self, action: &[f64]) -> Result<Vec<Vec<f64>>, EnvError> {
        if action.len() != self.spec.act_dim() {
            return Err(EnvError::ActionLength {
                env: self.spec.base.id.clone(),
                expected: self.spec.act_dim(),
                got: action.len(),
            });
        }
        Ok(self
            .spec
            .agents
            .iter()
            .map(|a| a.actions.iter().map(|&i| action[i]).collect())
            .collect())
    }

    /// `map_global_state_to_local_observations`: each agent's observation taken from a state
    /// vector. None when some agent observes a value the state does not hold (see
    /// `envspec::multi_agent::Agent::state_index`).
    pub fn global_state_to_local(&self, state: &[f64]) -> Option<Vec<Vec<f64>>> {
        if state.len() != self.spec.state_dim() {
            return None;
        }
        self.spec
            .agents
            .iter()
            .map(|a| {
                a.state_index
                    .as_ref()
                    .map(|ix| ix.iter().map(|&i| state[i]).collect())
            })
            .collect()
    }

    /// `map_local_observations_to_global_state`: the state rebuilt from every agent's
    /// observation. Errors when some state entry is observed by no agent, when two observations
    /// disagree about an entry, or when the mapping does not exist.
    pub fn local_observations_to_global(&self, obs: &[&[f64]]) -> Result<Vec<f64>, MappingError> {
        if obs.len() != self.spec.agents.len() {
            return Err(MappingError::Shape);
        }
        let mut state = vec![f64::NAN; self.spec.state_dim()];
        let mut set = vec![false; state.len()];
        for (a, o) in self.spec.agents.iter().zip(obs) {
            let ix = a.state_index.as_ref().ok_or(MappingError::NoMapping)?;
            if o.len() != ix.len() {
                return Err(MappingError::Shape);
            }
            for (&i, &x) in ix.iter().zip(o.iter()) {
                if set[i] && state[i].to_bits() != x.to_bits() {
                    return Err(MappingError::Conflict(i));
                }
                state[i] = x;
                set[i] = true;
            }
        }
        match set.iter().position(|s| !s) {
            Some(i) => Err(MappingError::Undefined(i)),
            None => Ok(state),
        }
    }

    fn write_obs(&mut self) {
        let env = &self.env;
        for (agent, out) in self.spec.agents.iter().zip(self.obs.iter_mut()) {
            crate::observe::write_segments(&agent.observation, |f| env.field(f), out);
        }
    }
}

/// Check per-agent actions (one slice per agent, each of the agent's length) and write them into
/// their global positions in `out`. Shared by `step` (into a reused buffer: no allocation) and
/// `local_actions_to_global`.
fn scatter_local_actions(
    spec: &MultiAgentSpec,
    actions: &[&[f64]],
    out: &mut [f64],
) -> Result<(), EnvError> {
    if actions.len() != spec.agents.len() {
        return Err(EnvError::ActionLength {
            env: format!("{} (number of agents)", spec.base.id),
            expected: spec.agents.len(),
            got: actions.len(),
        });
    }
    for (a, act) in spec.agents.iter().zip(actions) {
        if act.len() != a.actions.len() {
            return Err(EnvError::ActionLength {
                env: format!("{} agent {}", spec.base.id, a.name),
                expected: a.actions.len(),
                got: act.len(),
            });
        }
        for (&g, &x) in a.actions.iter().zip(act.iter()) {
            out[g] = x;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use envspec::Field;

    /// An agent that observes the mass center through `extra` gets it computed, though the base
    /// spec (Ant-v5) reads no mass center itself.
    #[test]
    fn agents_observing_the_mass_center_get_it_updated() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let text = std::fs::read_to_string(root.join("specs/mamujoco/ant.toml")).unwrap();
        let base = root.join("specs/gymnasium/ant.toml");
        let text = text
            .replace(
                "base = \"../gymnasium/ant.toml\"",
                &format!("base = {:?}", base.display().to_string()),
            )
            .replace(
                "global_categories = [\"qpos\", \"qvel\"]",
                "global_categories = [\"qpos\", \"qvel\", \"com\"]",
            )
            .replace(
                "extra = { qpos = \"qpos[2:7]\", qvel = \"qvel[0:6]\" }",
                "extra = { qpos = \"qpos[2:7]\", qvel = \"qvel[0:6]\", com = \"mass_center\" }",
            );
        let dir = std::env::temp_dir().join(format!("envc-ma-com-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("ant_com.toml");
        std::fs::write(&path, text).unwrap();
        let mut env = MultiAgentEnv::from_spec_file(&path, &[]).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        assert!(!env.spec().base.reads(Field::MassCenter));
        env.reset(Some(3));
        env.step_global(&[0.3; 8]).unwrap();

        // Gymnasium's `mass_center`: Σ mass·xipos / Σ mass.
        let nbody = env.spec().base.model.nbody();
        let mass = env.env().model().body_mass();
        let xipos = env.env().field(Field::Xipos);
        let total: f64 = mass.iter().sum();
        let com: Vec<f64> = (0..3)
            .map(|j| (0..nbody).map(|b| mass[b] * xipos[3 * b + j]).sum::<f64>() / total)
            .collect();
        assert!(com[2].abs() > 0.1, "{com:?}");
        let obs = &env.observations()[0];
        let ours = &obs[obs.len() - 3..];
        for (a, b) in ours.iter().zip(&com) {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                "{ours:?} vs {com:?}"
            );
        }
    }
}
