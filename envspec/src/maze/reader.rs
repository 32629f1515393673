//! Reading a maze spec with locations: the `[maze]` table, maze-parameter overrides, the map
//! (inline or a map file, whose errors point into that file) and the layout checks.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::grid::{check_layout, read_grid};
use super::{MAZE_PARAMS, MazeLocations, MazeSpec, RewardType};
use crate::diagnostic::{Code, Diagnostic, Diagnostics, Location, SourceFile, suggest};
use crate::params::{Override, OverrideValue};
use crate::value::{Entry, Val, ValKind, parse_literal, read_document};

const MAZE_KEYS: &[&str] = &[
    "id",
    "description",
    "robot",
    "robot_params",
    "map",
    "maze_size_scaling",
    "maze_height",
    "reward_type",
    "continuing_task",
    "reset_target",
    "max_episode_steps",
    "position_noise_range",
    "velocity_clip",
    "goal_threshold",
];
const MAP_FILE_KEYS: &[&str] = &["name", "grid"];

fn unknown_key(e: &Entry, context: &str, allowed: &[&str]) -> Diagnostic {
    Diagnostic::new(Code::E0101, format!("unknown key `{}` in {context}", e.key))
        .at(e.key_loc.clone())
        .label(format!("expected one of: {}", allowed.join(", ")))
        .help_opt(suggest(&e.key, allowed.iter().copied()))
}

/// Load a maze spec with overrides (maze parameters by name; anything else goes to the robot).
pub fn load_maze(path: &Path, overrides: &[Override]) -> Result<MazeSpec, Diagnostics> {
    let (file, root) = read_document(path, None, "maze spec")?;
    from_document(&file, &root, overrides)
}

/// A maze spec from a document already read with [`read_document`] (`root` is the whole
/// document, with its `[maze]` table). Relative paths resolve against `file.path`'s directory.
/// Overrides of maze parameters ([`MAZE_PARAMS`]) replace `[maze]` values (a `map` path then
/// resolves against the working directory); any other override goes to the robot spec.
pub fn from_document(
    file: &Arc<SourceFile>,
    root: &Val,
    overrides: &[Override],
) -> Result<MazeSpec, Diagnostics> {
    let mut d = Diagnostics::default();
    let Some((maze, table)) = maze_table(file, root, &mut d) else {
        return Err(d);
    };
    let dir = file.path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let mut r = Reader {
        entries: table.to_vec(),
        maze_loc: maze.key_loc.clone(),
        d,
        grid_loc: None,
        cell_locs: vec![],
    };
    let (robot_overrides, map_dir) = r.apply_overrides(overrides, &dir);

    let id = r.string("id", true).unwrap_or_default();
    if let Some(loc) = r.get("id").map(|v| v.loc.clone())
        && let Some(bad) = crate::syntax::env_id_problem(&id, loc)
    {
        r.d.push(bad);
    }
    r.string("description", false);
    let robot = r
        .string("robot", true)
        .map(|s| dir.join(s))
        .unwrap_or_default();
    let (base_overrides, robot_params) = r.robot_layers(&dir, robot_overrides);
    let maze_size_scaling = r.positive("maze_size_scaling");
    let maze_height = r.positive("maze_height");
    let position_noise_range = r.position_noise_range();
    let goal_threshold = r.goal_threshold();
    let velocity_clip = r.float("velocity_clip");
    let continuing_task = r.boolean("continuing_task").unwrap_or(true);
    let reset_target = r.boolean("reset_target").unwrap_or(false);
    let reward_type = r.reward_type();
    let max_episode_steps = r.max_episode_steps();
    let grid = r.map(&map_dir);
    let locations = MazeLocations {
        maze: Some(r.maze_loc.clone()),
        robot: r.get("robot").map(|v| v.loc.clone()),
        map: r
            .grid_loc
            .take()
            .or_else(|| r.get("map").map(|v| v.loc.clone())),
        maze_size_scaling: r.get("maze_size_scaling").map(|v| v.loc.clone()),
        robot_params,
        cells: std::mem::take(&mut r.cell_locs),
    };
    r.d.into_result(MazeSpec {
        id,
        path: file.path.clone(),
        inputs: vec![],
        robot,
        robot_overrides: base_overrides,
        grid,
        maze_size_scaling,
        maze_height,
        reward_type,
        continuing_task,
        reset_target,
        max_episode_steps,
        position_noise_range,
        velocity_clip,
        goal_threshold,
        locations,
    })
}

/// The `[maze]` entry and its table, with unknown keys at the top level and in `[maze]`
/// reported; None when there is no `[maze]` table (reported).
fn maze_table<'a>(
    file: &Arc<SourceFile>,
    root: &'a Val,
    d: &mut Diagnostics,
) -> Option<(&'a Entry, &'a [Entry])> {
    let top = root.as_table().unwrap_or(&[]);
    for e in top.iter().filter(|e| e.key != "maze") {
        d.push(unknown_key(e, "a maze spec (top level)", &["maze"]));
    }
    let Some(maze) = top.iter().find(|e| e.key == "maze") else {
        d.push(
            Diagnostic::new(Code::E0103, "a maze spec needs a `[maze]` table")
                .at(Location::new(file, 0..0))
                .label("expected a [maze] table"),
        );
        return None;
    };
    let Some(table) = maze.value.as_table() else {
        d.push(maze.value.type_error("`maze`", "a table"));
        return None;
    };
    for e in table {
        if !MAZE_KEYS.contains(&e.key.as_str()) {
            d.push(unknown_key(e, "[maze]", MAZE_KEYS));
        }
    }
    Some((maze, table))
}

/// An override's value as a TOML value located in its own text (`<override NAME>`); text that is
/// not a TOML literal is a bare string.
fn override_val(o: &Override) -> Val {
    let text = match &o.value {
        OverrideValue::Text(t) => t.clone(),
        OverrideValue::Value(v) => v.to_string(),
    };
    let file = SourceFile::new(format!("<override {}>", o.name), text.clone());
    parse_literal(&file).unwrap_or_else(|| Val {
        kind: ValKind::Str(text.clone()),
        loc: Location::new(&file, 0..text.len()),
    })
}

struct Reader {
    entries: Vec<Entry>,
    maze_loc: Location,
    d: Diagnostics,
    /// Where the grid's cells are written (in the map file when `map` names one), and each cell.
    grid_loc: Option<Location>,
    cell_locs: Vec<Vec<Location>>,
}

impl Reader {
    fn get(&self, key: &str) -> Option<&Val> {
        self.entries.iter().find(|e| e.key == key).map(|e| &e.value)
    }

    /// Overrides of maze parameters replace (or add) `[maze]` entries; the rest are the robot's,
    /// returned with the directory a `map` path resolves against (the working directory once
    /// overridden).
    fn apply_overrides(&mut self, overrides: &[Override], dir: &Path) -> (Vec<Override>, PathBuf) {
        let mut robot_overrides = vec![];
        let mut map_dir = dir.to_path_buf();
        for o in overrides {
            if !MAZE_PARAMS.contains(&o.name.as_str()) {
                robot_overrides.push(o.clone());
                continue;
            }
            let v = override_val(o);
            if o.name == "map" {
                map_dir = PathBuf::from(".");
            }
            let entry = Entry {
                key: o.name.clone(),
                key_loc: v.loc.clone(),
                value: v,
            };
            match self.entries.iter_mut().find(|e| e.key == o.name) {
                Some(e) => *e = entry,
                None => self.entries.push(entry),
            }
        }
        (robot_overrides, map_dir)
    }

    /// The robot's overrides: `robot_params`, then `robot_overrides` (a registry family's or a
    /// user's); and where each `robot_params` entry the robot receives is written.
    fn robot_layers(
        &mut self,
        dir: &Path,
        robot_overrides: Vec<Override>,
    ) -> (Vec<Override>, Vec<(String, Location)>) {
        let mut base_overrides = self.robot_params(dir);
        let robot_params = self
            .get("robot_params")
            .and_then(Val::as_table)
            .unwrap_or(&[])
            .iter()
            .filter(|e| !robot_overrides.iter().any(|o| o.name == e.key))
            .map(|e| {
                let span = e.key_loc.span.start..e.value.loc.span.end;
                (e.key.clone(), Location::new(&e.key_loc.file, span))
            })
            .collect();
        // A registry family's overrides replace the spec's own `robot_params` of the same name (a
        // layer, not a user's duplicate, which E0205 refuses).
        base_overrides.retain(|o| !robot_overrides.iter().any(|r| r.name == o.name));
        base_overrides.extend(robot_overrides);
        (base_overrides, robot_params)
    }

    /// `position_noise_range`, 0.25 by default (E0105 below 0, E0110 beyond the maze scale).
    fn position_noise_range(&mut self) -> f64 {
        let position_noise_range = self.float("position_noise_range").unwrap_or(0.25);
        if position_noise_range < 0.0 {
            let loc = self.get("position_noise_range").map(|v| v.loc.clone());
            self.d.push(
                Diagnostic::new(
                    Code::E0105,
                    format!("`position_noise_range` is {position_noise_range}"),
                )
                .at_opt(loc)
                .label("expected a number ≥ 0 (the reference's is 0.25)"),
            );
        }
        self.within_maze_scale("position_noise_range", position_noise_range);
        position_noise_range
    }

    fn missing(&mut self, key: &str, expected: &str) {
        self.d.push(
            Diagnostic::new(Code::E0103, format!("missing `{key}` in [maze]"))
                .at(self.maze_loc.clone())
                .label(format!("expected `{key}`: {expected}")),
        );
    }

    fn string(&mut self, key: &str, required: bool) -> Option<String> {
        match self.get(key).map(|v| (v.as_str().map(str::to_string), v)) {
            Some((Some(s), _)) => Some(s),
            Some((None, v)) => {
                let e = v.type_error(&format!("`{key}`"), "a string");
                self.d.push(e);
                None
            }
            None => {
                if required {
                    let what = if key == "robot" {
                        "the path of a robot task spec"
                    } else {
                        "a string"
                    };
                    self.missing(key, what);
                }
                None
            }
        }
    }

    /// A finite number (E0102 for another type, E0105 for inf / nan).
    fn float(&mut self, key: &str) -> Option<f64> {
        let v = self.get(key)?;
        let e = match v.as_f64() {
            Some(x) if x.is_finite() => return Some(x),
            Some(x) => Diagnostic::new(Code::E0105, format!("`{key}` is {x}"))
                .at(v.loc.clone())
                .label("expected a finite number"),
            None => v.type_error(&format!("`{key}`"), "a number"),
        };
        self.d.push(e);
        None
    }

    /// The goal's reach (E0803 below 0, where the goal term would find it without a location).
    fn goal_threshold(&mut self) -> f64 {
        let Some(x) = self.float("goal_threshold") else {
            return 0.45;
        };
        if x < 0.0 {
            let loc = self.get("goal_threshold").map(|v| v.loc.clone());
            self.d.push(
                Diagnostic::new(Code::E0803, format!("`goal_threshold` is {x}"))
                    .at_opt(loc)
                    .label("expected a distance ≥ 0 (the reference's is 0.45)"),
            );
        }
        x
    }

    fn positive(&mut self, key: &str) -> f64 {
        let Some(x) = self.float(key) else {
            if self.get(key).is_none() {
                self.missing(key, "a positive number");
            }
            return 0.0;
        };
        if x <= 0.0 {
            let loc = self.get(key).map(|v| v.loc.clone());
            self.d.push(
                Diagnostic::new(Code::E0105, format!("`{key}` is {x}"))
                    .at_opt(loc)
                    .label("expected a positive number"),
            );
        }
        self.within_maze_scale(key, x);
        x
    }

    /// A maze length or noise beyond `limits::MAX_MAZE_SCALE` (E0110): the walls would leave
    /// MuJoCo's range, or the noise draw overflow.
    fn within_maze_scale(&mut self, key: &str, x: f64) {
        let max = crate::limits::MAX_MAZE_SCALE;
        if x.abs() > max {
            let loc = self.get(key).map(|v| v.loc.clone());
            self.d.push(
                Diagnostic::new(
                    Code::E0110,
                    format!("`{key}` is {x}, beyond envc's limit of {max}"),
                )
                .at_opt(loc)
                .label(format!("expected at most {max}"))
                .help("see docs/limits.md"),
            );
        }
    }

    fn boolean(&mut self, key: &str) -> Option<bool> {
        let v = self.get(key)?;
        match v.kind {
            ValKind::Bool(b) => Some(b),
            _ => {
                let e = v.type_error(&format!("`{key}`"), "true or false");
                self.d.push(e);
                None
            }
        }
    }

    fn reward_type(&mut self) -> RewardType {
        let Some(v) = self.get("reward_type") else {
            return RewardType::Sparse;
        };
        let e = match v.as_str() {
            Some("sparse") => return RewardType::Sparse,
            Some("dense") => return RewardType::Dense,
            Some(s) => Diagnostic::new(Code::E0104, format!("unknown reward_type `{s}`"))
                .at(v.loc.clone())
                .label("expected \"sparse\" or \"dense\"")
                .help_opt(suggest(s, ["sparse", "dense"])),
            None => v.type_error("`reward_type`", "\"sparse\" or \"dense\""),
        };
        self.d.push(e);
        RewardType::Sparse
    }

    fn max_episode_steps(&mut self) -> Option<u64> {
        let v = self.get("max_episode_steps")?;
        let e = match v.kind {
            ValKind::Int(0) => return None,
            ValKind::Int(n) if n > 0 => return Some(n as u64),
            ValKind::Int(n) => Diagnostic::new(Code::E0105, format!("`max_episode_steps` is {n}"))
                .at(v.loc.clone())
                .label("expected a non-negative integer (0: no time limit)"),
            _ => v.type_error("`max_episode_steps`", "a non-negative integer"),
        };
        self.d.push(e);
        None
    }

    /// `robot_params` as overrides; string values starting with `./` or `../` are paths
    /// relative to the maze spec.
    fn robot_params(&mut self, dir: &Path) -> Vec<Override> {
        let Some(v) = self.get("robot_params") else {
            return vec![];
        };
        let Some(t) = v.as_table() else {
            let e = v.type_error("`robot_params`", "a table");
            self.d.push(e);
            return vec![];
        };
        t.iter()
            .map(|e| {
                let text = match e.value.as_str() {
                    Some(s) if s.starts_with("../") || s.starts_with("./") => {
                        format!("{:?}", dir.join(s).display().to_string())
                    }
                    _ => e.value.to_toml(),
                };
                Override::text(&e.key, &text)
            })
            .collect()
    }

    /// The grid (inline or from a map file) after the layout checks; empty after an error.
    fn map(&mut self, map_dir: &Path) -> Vec<Vec<super::Cell>> {
        let Some(v) = self.get("map").cloned() else {
            self.missing("map", "a grid or the path of a map file");
            return vec![];
        };
        let (grid_val, map_loc) = match v.as_str() {
            Some(s) if s.trim_end().ends_with(".toml") => {
                match read_map_file(&map_dir.join(s.trim()), &v.loc) {
                    Ok(g) => {
                        let loc = g.loc.clone();
                        (g, loc)
                    }
                    Err(e) => {
                        self.d.0.extend(e.0);
                        return vec![];
                    }
                }
            }
            _ => (v.clone(), v.loc.clone()),
        };
        let Some(grid) = read_grid(&grid_val, &mut self.d) else {
            return vec![];
        };
        let before = self.d.len();
        check_layout(&grid, &map_loc, &mut self.d);
        if self.d.len() > before {
            return vec![];
        }
        self.grid_loc = Some(map_loc);
        self.cell_locs = grid
            .cells
            .iter()
            .map(|row| row.iter().map(|(_, l)| l.clone()).collect())
            .collect();
        grid.cells()
    }
}

/// The `grid` value of a map file (`name = "..."`, `grid = """..."""`).
fn read_map_file(path: &Path, at: &Location) -> Result<Val, Diagnostics> {
    let (file, root) = read_document(path, Some(at), "map").map_err(|mut e| {
        for x in &mut e.0 {
            if x.code == Code::E0600 {
                x.help = Some(
                    "a map path in a spec is relative to the spec's directory; in an override, to the working directory".into(),
                );
            }
        }
        e
    })?;
    let mut d = Diagnostics::default();
    let top = root.as_table().unwrap_or(&[]);
    for e in top {
        if !MAP_FILE_KEYS.contains(&e.key.as_str()) {
            d.push(unknown_key(e, "a map file", MAP_FILE_KEYS));
        }
    }
    if let Some(e) = top.iter().find(|e| e.key == "name")
        && e.value.as_str().is_none()
    {
        d.push(e.value.type_error("`name`", "a string"));
    }
    match top.iter().find(|e| e.key == "grid") {
        Some(e) => d.into_result(e.value.clone()),
        None => {
            d.push(
                Diagnostic::new(Code::E0103, "a map file needs `grid`")
                    .at(Location::new(&file, 0..0))
                    .label("expected `grid = \"\"\"...\"\"\"`"),
            );
            Err(d)
        }
    }
}
