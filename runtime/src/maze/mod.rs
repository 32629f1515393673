//! Maze envs: a maze spec (layout, envspec::maze) composed with any robot task spec, run with the
//! semantics of Gymnasium-Robotics 1.4.2's `maze_v4.MazeEnv` (PointMaze-v3, AntMaze-v4/v5).
//!
//! World building: the robot's model is loaded into an mjSpec (with the robot spec's own model
//! edits), the wall blocks and the goal marker are added to its world body (they inherit the robot
//! file's geom defaults, as the reference's XML rewrite does), and the result is compiled in
//! memory: no temporary files.
//!
//! ```no_run
//! use envc::maze::MazeEnv;
//! let mut env = MazeEnv::make("PointMaze_UMaze-v3", &[])?;
//! let (obs, _success) = env.reset(Some(0), None)?;
//! let obs = obs.clone();
//! let step = env.step(&[0.5, 0.5])?;
//! println!("{:?} reward {} success {}", obs.desired_goal, step.reward, step.success);
//! # Ok::<(), envc::EnvError>(())
//! ```

use std::path::Path;
use std::sync::Arc;

use envspec::goal::GoalTask;
use envspec::ir::GoalNorm;
use envspec::maze::{Cell, Layout, MazeSpec};
use envspec::{Code, Diagnostic, Diagnostics, Override, ResolvedSpec};
use mujoco_rs::prelude::*;

use crate::env::{BoxSpace, Env, Info};
use crate::error::EnvError;
use crate::numerics::Profile;
use crate::rng::NumpyRng;

mod fit;
mod joint;

/// The goal-conditioned observation (Gymnasium-Robotics' dict; keys sort as achieved_goal,
/// desired_goal, observation in the reference's `spaces.Dict`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MazeObs {
    /// The robot spec's observation.
    pub observation: Vec<f64>,
    /// `qpos[0:2]`: the robot's root x, y.
    pub achieved_goal: [f64; 2],
    /// The current goal x, y.
    pub desired_goal: [f64; 2],
}

/// `reset(options=...)`: cells (row, col) to place the goal / the robot in (any non-wall cell).
#[derive(Clone, Copy, Debug, Default)]
pub struct ResetOptions {
    /// The cell to put the goal in (None: drawn as the reference does).
    pub goal_cell: Option<[usize; 2]>,
    /// The cell to start the robot in (None: drawn as the reference does).
    pub reset_cell: Option<[usize; 2]>,
}

/// One maze step.
#[derive(Debug)]
pub struct MazeStep<'a> {
    /// The observation dict after the step.
    pub obs: &'a MazeObs,
    /// The step's reward: the goal terms against the current goal.
    pub reward: f64,
    /// Whether the episode ended: the goal was reached, unless the task is continuing.
    pub terminated: bool,
    /// Whether the time limit cut the episode short.
    pub truncated: bool,
    /// `info["success"]`: the robot is within the goal threshold of the goal.
    pub success: bool,
    /// The robot's own info (the maze forwards it; `success` is added above).
    pub robot_info: Info<'a>,
}

/// A maze env.
pub struct MazeEnv {
    spec: Arc<MazeSpec>,
    /// The goal terms (`MazeSpec::goal_task`); the robot env runs them as its reward and
    /// termination, against its goal vector (kept equal to `goal`).
    task: GoalTask,
    robot: Env,
    layout: Layout,
    rng: Option<NumpyRng>,
    goal: [f64; 2],
    /// Where the goal marker is drawn: the goal in force at the last kinematics pass (reset's
    /// forward, or the last step's physics). The reference moves the marker's `site_pos` after a
    /// step resamples the goal, so its `site_xpos` follows only at the next step.
    marker: [f64; 2],
    obs: MazeObs,
    elapsed: u64,
    has_reset: bool,
    success: bool,
}

/// A maze's robot must be a task spec: a maze or a multi-agent spec without `[env]` there is one
/// error at `robot = ...` (it was the robot file's every missing task key, at 1:1).
fn check_robot_kind(spec: &MazeSpec) -> Result<(), EnvError> {
    let Ok((_, root)) = envspec::value::read_document(&spec.robot, None, "spec") else {
        return Ok(()); // the robot's load says why
    };
    let top = root.as_table().unwrap_or(&[]);
    let has = |k: &str| top.iter().any(|e| e.key == k);
    let same = match (spec.robot.canonicalize(), spec.path.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => spec.robot == spec.path,
    };
    let (code, what) = if same {
        (
            Code::E0108,
            "`robot` names this maze file itself".to_string(),
        )
    } else if has("maze") {
        (
            Code::E0108,
            format!(
                "`robot` names a maze spec ({}), not a robot task spec",
                spec.robot.display()
            ),
        )
    } else if has("agents") && !has("env") {
        (
            Code::E0122,
            format!(
                "`robot` names a multi-agent spec ({}), not a robot task spec",
                spec.robot.display()
            ),
        )
    } else {
        return Ok(());
    };
    Err(EnvError::Spec(
        Diagnostic::new(code, what)
            .at_opt(spec.locations.robot.clone())
            .label("expected the path of a robot task spec (one with `[env]`)")
            .help("e.g. robot = \"../../gymnasium/ant.toml\"")
            .into(),
    ))
}

/// Whether `word` occurs in `text` as a whole name (not inside a longer one).
fn names_word(text: &str, word: &str) -> bool {
    let name = |c: char| c.is_alphanumeric() || c == '_';
    text.match_indices(word).any(|(i, _)| {
        !text[..i].chars().next_back().is_some_and(name)
            && !text[i + word.len()..].chars().next().is_some_and(name)
    })
}

/// The robot spec's errors that have no place in the robot's own file point into the maze spec:
/// a `robot_params` value at its entry, an unreadable robot file at `robot = ...`.
fn locate_robot_errors(mut d: Diagnostics, spec: &MazeSpec) -> Diagnostics {
    for x in &mut d.0 {
        let in_override = x
            .location
            .as_ref()
            .is_some_and(|l| l.file.path.to_string_lossy().starts_with("<override "));
        if x.location.is_some() && !in_override {
            continue;
        }
        let param = spec
            .locations
            .robot_params
            .iter()
            .find(|(k, _)| names_word(&x.message, k));
        if let Some((_, loc)) = param {
            x.location = Some(loc.clone());
        } else if x.location.is_none() && matches!(x.code, Code::E0600 | Code::E0601) {
            x.location = spec.locations.robot.clone();
        }
    }
    d
}

impl MazeEnv {
    /// A registered maze id (e.g. `AntMaze_Medium_Diverse_GRDense-v5`) or a maze spec file, with
    /// overrides (maze parameters by name, anything else goes to the robot spec).
    pub fn make(id_or_path: &str, overrides: &[Override]) -> Result<MazeEnv, EnvError> {
        match envspec::open(id_or_path, overrides)? {
            envspec::AnySpec::Maze(m) => MazeEnv::new(*m),
            other => Err(EnvError::Spec(
                Diagnostic::new(
                    Code::E0602,
                    format!("`{id_or_path}` is a {} spec, not a maze", other.kind()),
                )
                .help("open it with `envc::open`")
                .into(),
            )),
        }
    }

    /// Build the maze env of the spec file at `path`, with overrides applied.
    pub fn from_spec_file(path: &Path, overrides: &[Override]) -> Result<MazeEnv, EnvError> {
        let spec = envspec::maze::load_maze(path, overrides)?;
        MazeEnv::new(spec)
    }

    /// Build the maze world around the robot and the env.
    pub fn new(spec: MazeSpec) -> Result<MazeEnv, EnvError> {
        check_robot_kind(&spec)?;
        let robot_spec = envspec::load(&spec.robot, &spec.robot_overrides)
            .map_err(|d| locate_robot_errors(d, &spec))?;
        if robot_spec.model.nq < 2 {
            return Err(EnvError::Spec(
                Diagnostic::new(
                    Code::E0707,
                    format!(
                        "the robot `{}` has {}; a maze robot needs its root x, y in qpos[0:2]",
                        robot_spec.id,
                        match robot_spec.model.nq {
                            1 => "1 qpos entry".to_string(),
                            n => format!("{n} qpos entries"),
                        }
                    ),
                )
                .at_opt(spec.locations.robot.clone())
                .label("expected a robot with a free joint or x, y slide joints first")
                .into(),
            ));
        }
        // A MazeSpec built by hand skips the reader's layout checks.
        let layout = spec.layout();
        for (none, code, what, cell) in [
            (layout.goals.is_empty(), Code::E0703, "goal", "a `g`"),
            (layout.resets.is_empty(), Code::E0704, "reset", "an `r`"),
        ] {
            if none {
                return Err(EnvError::Spec(
                    Diagnostic::new(code, format!("the maze has no {what} cell"))
                        .at_opt(spec.locations.map.clone())
                        .label(format!("expected {cell} or `c` cell, or a free `0` cell"))
                        .into(),
                ));
            }
        }
        let model = Arc::new(build_world(&spec, &robot_spec)?);
        fit::check_robot_fits(&spec, &robot_spec, &model)?;
        // The goal terms' errors have no place of their own: the threshold's is the maze's, the
        // others (a robot with a goal vector of its own) the robot's.
        let place = |d: Diagnostic| {
            let (at, what) = match d.code {
                Code::E0803 => (&spec.locations.maze, "the maze's goal task"),
                _ => (
                    &spec.locations.robot,
                    "the robot spec, with goal terms of its own",
                ),
            };
            let d = match (&d.location, &d.label) {
                (Some(_), _) => d,
                (None, None) => d.at_opt(at.clone()).label(what),
                (None, Some(_)) => d.at_opt(at.clone()),
            };
            Diagnostics::from(d)
        };
        let task = spec.goal_task(&robot_spec.model).map_err(place)?;
        let robot_spec = task.apply(robot_spec).map_err(place)?;
        let robot = Env::with_world_model(Arc::new(robot_spec), model, 1)?;
        let obs = MazeObs {
            observation: vec![0.0; robot.obs_dim()],
            ..Default::default()
        };
        Ok(MazeEnv {
            spec: Arc::new(spec),
            task,
            robot,
            layout,
            rng: None,
            goal: [0.0; 2],
            marker: [0.0; 2],
            obs,
            elapsed: 0,
            has_reset: false,
            success: false,
        })
    }

    /// The resolved maze spec.
    pub fn spec(&self) -> &MazeSpec {
        &self.spec
    }
    /// The env's id.
    pub fn id(&self) -> &str {
        &self.spec.id
    }
    /// Render the maze world with its goal marker (the `target` site) where Gymnasium-Robotics'
    /// `update_target_site_pos` shows it: at the goal of the last kinematics pass, so a goal
    /// resampled by a step shows from the next step (docs/rendering.md).
    pub fn render(
        &mut self,
        mode: crate::render::RenderMode,
    ) -> Result<crate::render::Frame<'_>, EnvError> {
        let (goal, z) = (
            self.marker,
            self.spec.maze_height / 2.0 * self.spec.maze_size_scaling,
        );
        self.robot.render_with(mode, |d| {
            let site = mujoco_rs::mujoco_c::mjtObj::mjOBJ_SITE;
            if let Some(id) = crate::mj::names::id(d.model().ffi(), site, "target")
                && let Some(p) = d.site_xpos_mut().get_mut(id)
            {
                // The target hangs on the world body: its world position is its local one.
                *p = [goal[0], goal[1], z];
            }
        })
    }
    /// The robot env inside the maze (its model is the compiled maze world).
    pub fn robot(&self) -> &Env {
        &self.robot
    }
    /// The robot env, for settings and rendering (stepping it directly would bypass the maze).
    pub(crate) fn robot_mut(&mut self) -> &mut Env {
        &mut self.robot
    }
    /// `info["success"]` of the last reset or step.
    pub fn success(&self) -> bool {
        self.success
    }
    /// After a failure: `step` refuses (E1103) until the next `reset`.
    pub fn require_reset(&mut self) {
        self.has_reset = false;
        self.robot.require_reset();
    }
    /// The numerics profile (norms, the dense reward's `exp`); see `Env::set_numerics`.
    pub fn numerics(&self) -> Profile {
        self.robot.numerics()
    }
    /// Compute as the reference does under `profile` from now on.
    pub fn set_numerics(&mut self, profile: Profile) {
        self.robot.set_numerics(profile);
    }
    /// The goal terms: the reward term, the reached check (success, termination).
    pub fn goal_task(&self) -> &GoalTask {
        &self.task
    }
    /// `np.linalg.norm(a - b)` under this env's profile (the start cell's distance to the goal).
    fn dist_blas(&self, a: [f64; 2], b: [f64; 2]) -> f64 {
        crate::goal::distance(GoalNorm::Blas, self.robot.numerics(), 2, &|k| (a[k], b[k]))
    }
    /// The compiled model (maze walls included), shared by every env built from it.
    pub fn model(&self) -> &Arc<MjModel> {
        self.robot.model()
    }
    /// The robot's action space.
    pub fn action_space(&self) -> &BoxSpace {
        self.robot.action_space()
    }
    /// The action's length.
    pub fn act_dim(&self) -> usize {
        self.robot.act_dim()
    }
    /// Size of `observation` (`achieved_goal` and `desired_goal` have 2 entries).
    pub fn observation_dim(&self) -> usize {
        self.robot.obs_dim()
    }
    /// The time limit in steps (None: no limit).
    pub fn max_episode_steps(&self) -> Option<u64> {
        self.spec.max_episode_steps
    }
    /// Seconds of simulated time per step.
    pub fn dt(&self) -> f64 {
        self.robot.dt()
    }
    /// The current observation dict.
    pub fn obs(&self) -> &MazeObs {
        &self.obs
    }
    /// The goal candidates and reset candidates (cell centres, in draw order).
    pub fn layout(&self) -> &Layout {
        &self.layout
    }
    /// MuJoCo warnings raised while loading or running the env.
    pub fn warnings(&self) -> &[String] {
        self.robot.warnings()
    }

    fn rng(&mut self) -> &mut NumpyRng {
        self.rng.as_mut().expect("seeded in reset")
    }

    fn noisy(&mut self, mut xy: [f64; 2]) -> [f64; 2] {
        let (r, s) = (self.spec.position_noise_range, self.spec.maze_size_scaling);
        let nx = self.rng().uniform(-r, r) * s;
        let ny = self.rng().uniform(-r, r) * s;
        xy[0] += nx;
        xy[1] += ny;
        xy
    }

    fn sample_goal(&mut self) -> [f64; 2] {
        let n = self.layout.goals.len() as i64;
        let k = self.rng().integers(0, n) as usize;
        self.layout.goals[k]
    }

    fn check_cell(&self, cell: [usize; 2], what: &str) -> Result<(), EnvError> {
        let ok = cell[0] < self.spec.rows()
            && cell[1] < self.spec.cols()
            && self.spec.grid[cell[0]][cell[1]] != Cell::Wall;
        if ok {
            Ok(())
        } else {
            Err(EnvError::Spec(
                Diagnostic::new(
                    Code::E0708,
                    format!(
                        "{what} {cell:?} is not a free cell of the {}×{} maze",
                        self.spec.rows(),
                        self.spec.cols()
                    ),
                )
                .at_opt(
                    // The wall cell itself, or the whole map for a cell outside it.
                    self.spec
                        .locations
                        .cells
                        .get(cell[0])
                        .and_then(|r| r.get(cell[1]))
                        .or(self.spec.locations.map.as_ref())
                        .cloned(),
                )
                .label("expected a free cell: cells are [row, col] from 0, walls are `1`")
                .into(),
            ))
        }
    }

    /// Gymnasium-Robotics `reset(seed=..., options=...)`: goal, then reset position, then the
    /// robot's own reset (with the same seed). Returns the observation and `info["success"]`
    /// (the robot's reset info is in `robot().reset_info()`).
    pub fn reset(
        &mut self,
        seed: Option<u64>,
        options: Option<ResetOptions>,
    ) -> Result<(&MazeObs, bool), EnvError> {
        let o = options.unwrap_or_default();
        if let Some(c) = o.goal_cell {
            self.check_cell(c, "goal_cell")?;
        }
        if let Some(c) = o.reset_cell {
            self.check_cell(c, "reset_cell")?;
        }
        match seed {
            Some(s) => self.rng = Some(NumpyRng::from_seed(s)),
            None if self.rng.is_none() => self.rng = Some(NumpyRng::from_entropy()),
            None => {}
        }
        let goal = match o.goal_cell {
            Some([i, j]) => self.spec.cell_xy(i, j),
            None => self.sample_goal(),
        };
        self.goal = self.noisy(goal);
        let reset = match o.reset_cell {
            Some([i, j]) => self.spec.cell_xy(i, j),
            None => {
                let lim = 0.5 * self.spec.maze_size_scaling;
                let n = self.layout.resets.len() as i64;
                let mut r = self.goal;
                // The reference loops forever when no reset cell is far enough (trap M15); envc
                // gives up after many draws and keeps the last one.
                let mut tries = 0u32;
                while self.dist_blas(r, self.goal) <= lim && tries < 1_000_000 {
                    let k = self.rng().integers(0, n) as usize;
                    r = self.layout.resets[k];
                    tries += 1;
                }
                r
            }
        };
        let reset = self.noisy(reset);
        let init = self.robot.init_qpos_mut();
        init[0] = reset[0];
        init[1] = reset[1];
        self.robot.goal_mut().copy_from_slice(&self.goal);
        self.marker = self.goal;
        let (obs, _) = self.robot.reset(seed);
        self.obs.observation.copy_from_slice(obs);
        self.fill_goals();
        self.success = self.robot.goal_reached(&self.task.reached);
        self.elapsed = 0;
        self.has_reset = true;
        Ok((&self.obs, self.success))
    }

    /// `achieved_goal` is what the goal terms read as `achieved` (`qpos[0:2]`).
    fn fill_goals(&mut self) {
        let a = &self.task.reached.distance.achieved;
        let f = self.robot.field(a.field);
        self.obs.achieved_goal = [f[a.indices[0]], f[a.indices[1]]];
        self.obs.desired_goal = self.goal;
    }

    /// Gymnasium-Robotics `step`: the robot steps (its reward and termination are ignored), then
    /// reward, termination and success against the current goal, then `update_goal`.
    pub fn step(&mut self, action: &[f64]) -> Result<MazeStep<'_>, EnvError> {
        self.check_action(crate::JointAction::F64(action))?;
        if let Some(v) = self.spec.velocity_clip {
            self.robot.clip_qvel(v)?;
        }
        self.marker = self.goal;
        let s = self.robot.step(action)?;
        let (reward, terminated) = (s.reward, s.terminated);
        self.obs.observation.copy_from_slice(self.robot.obs());
        Ok(self.after_step(reward, terminated))
    }

    /// `step` with a float32 action, as a float32 policy calls the reference (the robot's action
    /// costs in its info are then float32 numbers, as numpy computes them).
    pub fn step_f32(&mut self, action: &[f32]) -> Result<MazeStep<'_>, EnvError> {
        self.check_action(crate::JointAction::F32(action))?;
        if let Some(v) = self.spec.velocity_clip {
            self.robot.clip_qvel(v)?;
        }
        self.marker = self.goal;
        let s = self.robot.step_f32(action)?;
        let (reward, terminated) = (s.reward, s.terminated);
        self.obs.observation.copy_from_slice(self.robot.obs());
        Ok(self.after_step(reward, terminated))
    }

    fn check_action(&self, action: crate::JointAction<'_>) -> Result<(), EnvError> {
        crate::joint_env::check_action(&self.spec.id, self.robot.act_dim(), action, || {
            (!self.has_reset).then(|| self.robot.reset_error().unwrap_or(EnvError::NotReset))
        })
    }

    /// `reward` and `terminated` are the robot env's: the goal terms, evaluated against the goal
    /// before any update (`desired_goal`).
    fn after_step(&mut self, reward: f64, terminated: bool) -> MazeStep<'_> {
        self.fill_goals();
        self.success = self.robot.goal_reached(&self.task.reached);
        self.update_goal(self.obs.achieved_goal);
        self.elapsed += 1;
        let truncated = self
            .spec
            .max_episode_steps
            .is_some_and(|m| self.elapsed >= m);
        MazeStep {
            obs: &self.obs,
            reward,
            terminated,
            truncated,
            success: self.success,
            robot_info: self.robot.step_info(),
        }
    }

    /// The goal task's reached check on given goals.
    fn reached(&self, achieved: [f64; 2], desired: [f64; 2]) -> bool {
        crate::goal::reached(&self.task.reached, self.numerics(), &achieved, &desired)
            .unwrap_or(false)
    }

    /// `compute_reward` over a batch (hindsight relabelling): `out[k]` is the reward term's value
    /// for `achieved[k]` against `desired[k]`, exactly as the step reward.
    pub fn compute_reward(&self, achieved: &[[f64; 2]], desired: &[[f64; 2]], out: &mut [f64]) {
        let p = self.numerics();
        for ((a, d), o) in achieved.iter().zip(desired).zip(out.iter_mut()) {
            *o = crate::goal::term_value(&self.task.reward, p, a, d, &|_, k| k).unwrap_or(f64::NAN);
        }
    }

    /// `compute_terminated`: whether a termination condition of the robot env (reaching the goal,
    /// unless the task is continuing) holds for these goals.
    pub fn compute_terminated(&self, achieved: [f64; 2], desired: [f64; 2]) -> bool {
        let p = self.numerics();
        self.robot
            .spec()
            .termination
            .iter()
            .any(|t| crate::goal::reached(&t.reached, p, &achieved, &desired).unwrap_or(false))
    }

    /// `compute_truncated`: always false (the time limit truncates).
    pub fn compute_truncated(&self, _achieved: [f64; 2], _desired: [f64; 2]) -> bool {
        false
    }

    /// With `continuing_task` and `reset_target`, a reached goal is redrawn until it is not
    /// reached (the robot env's goal vector follows).
    fn update_goal(&mut self, achieved: [f64; 2]) {
        if self.spec.continuing_task
            && self.spec.reset_target
            && self.reached(achieved, self.goal)
            && self.layout.goals.len() > 1
        {
            let mut tries = 0u32;
            while self.reached(achieved, self.goal) && tries < 1_000_000 {
                let g = self.sample_goal();
                self.goal = self.noisy(g);
                tries += 1;
            }
            self.robot.goal_mut().copy_from_slice(&self.goal);
        }
    }

    /// The current goal (the next step's `desired_goal`).
    pub fn goal(&self) -> [f64; 2] {
        self.goal
    }
    /// Steps taken since the last reset.
    pub fn elapsed_steps(&self) -> u64 {
        self.elapsed
    }
}

/// The robot's model with the maze added to its world body: one box per wall cell (named
/// `block_i_j`, row-major) and the `target` site, as `Maze.make_maze` writes them.
pub fn build_world(maze: &MazeSpec, robot: &ResolvedSpec) -> Result<MjModel, EnvError> {
    crate::mj::log::install();
    let bad = |message: String| EnvError::Compile {
        path: robot.model_path.clone(),
        message,
    };
    // A robot element with a name the maze gives its own (E0106, at `robot = ...`).
    let taken = |name: &str, what: &str| {
        EnvError::Spec(
            Diagnostic::new(
                Code::E0106,
                format!(
                    "the robot's model {} already has an element named `{name}`, the name the maze gives {what}",
                    robot.model_path.display()
                ),
            )
            .at_opt(maze.locations.robot.clone())
            .label("a robot whose model uses a name of the maze's world")
            .help("rename that element of the robot's model (the maze names its walls `block_<row>_<col>` and its goal site `target`)")
            .into(),
        )
    };
    let mut spec =
        crate::model_build::load_edited(&robot.model_path, &robot.model_edits).map_err(&bad)?;
    let s = maze.maze_size_scaling;
    let h = maze.maze_height;
    let z = h / 2.0 * s;
    for &(i, j, x, y) in &maze.layout().walls {
        let g = spec.world_body_mut().add_geom();
        g.set_name(&format!("block_{i}_{j}"))
            .map_err(|_| taken(&format!("block_{i}_{j}"), "its wall blocks"))?;
        g.set_type(MjtGeomBase::mjGEOM_BOX);
        *g.pos_mut() = [x, y, z];
        *g.size_mut() = [0.5 * s, 0.5 * s, z];
        g.set_material("");
        g.set_contype(1);
        g.set_conaffinity(1);
        *g.rgba_mut() = [0.7, 0.5, 0.3, 1.0];
    }
    let t = spec.world_body_mut().add_site();
    t.set_name("target")
        .map_err(|_| taken("target", "its goal marker"))?;
    t.set_type(MjtGeomBase::mjGEOM_SPHERE);
    *t.pos_mut() = [0.0, 0.0, z];
    t.size_mut()[0] = 0.2 * s;
    *t.rgba_mut() = [1.0, 0.0, 0.0, 0.7];
    let mut model = crate::mj::catch::compile(&mut spec).map_err(bad)?;
    crate::model_build::fill_keyframes(&robot.model_edits, &mut model);
    Ok(model)
}
