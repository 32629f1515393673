//! Errors for people: every problem carries a stable code, the file, line and column, the offending
//! line with a caret, what was expected, and (where one exists) a near-miss suggestion.
//!
//! Rendering is done here rather than with a snippet crate: we need one primary span per
//! diagnostic and a fixed, test-pinned format, which is a few dozen lines.

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A spec (or model) file held in memory so errors can quote it.
#[derive(Debug)]
pub struct SourceFile {
    /// The path errors print (as given, not canonicalized).
    pub path: PathBuf,
    /// The whole text, for quoting the line at a location.
    pub text: String,
    line_starts: Vec<usize>,
}

impl SourceFile {
    /// Hold `text` read from `path`, indexing its line starts.
    pub fn new(path: impl Into<PathBuf>, text: String) -> Arc<Self> {
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Arc::new(SourceFile {
            path: path.into(),
            text,
            line_starts,
        })
    }

    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let line = self.line_starts.partition_point(|&s| s <= offset) - 1;
        let start = self.line_starts[line];
        let col = self.text[start..offset].chars().count() + 1;
        (line + 1, col)
    }

    /// Byte offset of a 1-based line and column (in characters); None outside the file.
    pub fn offset(&self, line: usize, col: usize) -> Option<usize> {
        let start = *self.line_starts.get(line.checked_sub(1)?)?;
        let text = self.line_text(line);
        let within = match text.char_indices().nth(col.checked_sub(1)?) {
            Some((i, _)) => i,
            None => text.len(),
        };
        Some(start + within)
    }

    fn line_text(&self, line: usize) -> &str {
        let start = self.line_starts[line - 1];
        let end = self
            .line_starts
            .get(line)
            .copied()
            .unwrap_or(self.text.len());
        self.text[start..end].trim_end_matches(['\n', '\r'])
    }
}

/// A location: a byte range in a source file.
#[derive(Clone, Debug)]
pub struct Location {
    /// The file the range is in.
    pub file: Arc<SourceFile>,
    /// Byte range into the file's text.
    pub span: Range<usize>,
}

impl Location {
    /// The range `span` of `file`.
    pub fn new(file: &Arc<SourceFile>, span: Range<usize>) -> Self {
        Location {
            file: Arc::clone(file),
            span,
        }
    }

    /// `path:line:col`
    pub fn position(&self) -> String {
        let (line, col) = self.file.line_col(self.span.start);
        format!(
            "{}:{line}:{col}",
            escape(&self.file.path.display().to_string())
        )
    }
}

/// Stable error codes. Documented in `docs/errors.md`; never renumber.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Code {
    /// The file is not valid TOML.
    E0100,
    /// A key that the schema does not know.
    E0101,
    /// A value of the wrong type.
    E0102,
    /// A required key is missing.
    E0103,
    /// A string that is not one of the choices its key accepts (unknown kind, mode, ...).
    E0104,
    /// A number outside its allowed range (or beyond what 64 bits hold), or a reversed range.
    E0105,
    /// A name defined twice where names must be unique (actuators, info keys).
    E0106,
    /// A model element or field of the wrong kind for its use (an actuator on a free joint, a
    /// reset target outside qpos/qvel).
    E0107,
    /// A maze spec (`[maze]`) given where a robot task spec is expected.
    E0108,
    /// A multi-agent partition that does not drive every actuator exactly once.
    E0109,
    /// A value beyond envc's limits (`envspec::limits`): a file too large or not a regular file,
    /// a MuJoCo size that would exhaust memory, `frame_skip` or `max_episode_steps` too large, a
    /// reset condition that cannot be met.
    E0110,
    /// An `[env] id` Gymnasium cannot register (empty, a `/`, a space).
    E0111,
    /// An event's `elements` name no element of the model (a name it lacks, a pattern that
    /// matches none).
    E0150,
    /// An event's distribution parameters are invalid (a reversed or non-finite range, a
    /// log-uniform bound ≤ 0, a negative standard deviation).
    E0151,
    /// An event whose parts do not fit together: elements on a model-wide field or none on a
    /// per-element field, a push that is not an interval event or acts on no free joint, an
    /// interval without `interval_seconds` (or one on another mode).
    E0152,
    /// An event whose values would leave the field's limits (a timestep outside
    /// (0, `limits::MAX_TIMESTEP`], a negative mass, friction, damping, armature or kp).
    E0153,
    /// A `[joint_properties]` pattern that matches no hinge or slide joint of the model.
    E0160,
    /// A `[joint_properties]` value that does not fit: negative, not a range, or an actuator key
    /// reaching no actuator (or one of another kind).
    E0161,
    /// A `[keyframes.*]` table or a keyframe reset that does not fit: an unknown joint or
    /// keyframe, values of another count, a root draw on a model without a free joint.
    E0162,
    /// A manipulation table (`[init]`, `[end_effector]`, `[hold.*]`, `[goal]`) or a reset's
    /// `around` that does not fit the model or the spec: an unknown joint, site, body, actuator
    /// or record, values of another count, a goal selector beyond the goal vector.
    E0170,
    /// A state condition (a reward term's `only_if`, a `condition` info entry) or an observation
    /// `indicator` that does not fit: an unknown comparison, a source of more than one number
    /// without `norm = true`, neither a table nor a list of tables.
    E0180,
    /// A `derived[...]` selector naming no `[derived.*]` table above it, or an index beyond it.
    E0181,
    /// `[agents] base` leads back to a spec already on its chain of bases (a cycle).
    E0120,
    /// `[agents] base` names a multi-agent spec that has no task of its own.
    E0121,
    /// A maze's `robot` names a multi-agent spec that has no task of its own.
    E0122,
    /// A `[commands.*]` table that cannot be drawn: a component range reversed or not finite, a
    /// probability outside [0, 1], a negative resample interval, no components.
    E0130,
    /// A `command[...]` selector naming a command or component the spec does not declare.
    E0131,
    /// An `[actions]` table that does not fit the model: a default pose of another length, a
    /// negative gain, a non-finite scale, a reversed range; or `default_pose` read without it.
    E0132,
    /// A keyframe the model does not have, or an actuator that drives no joint (so the keyframe
    /// gives it no default position).
    E0133,
    /// A legged term naming a geom or body the model does not have, or feet and sites of
    /// different counts.
    E0134,
    /// A legged term over elements of the wrong kind: `joint_limits` over anything but hinge or
    /// slide joint positions, a non-positive `sigma`.
    E0135,
    /// An observation noise's `scale` or `level` negative, or their product beyond envc's limit.
    E0140,
    /// An observation `delay` or `[latency] action` that is not a step count within envc's limit.
    E0141,
    /// A reference to a parameter that the spec does not declare.
    E0201,
    /// An override names a parameter that the spec does not declare.
    E0202,
    /// An override value has the wrong type for its parameter.
    E0203,
    /// An override of a parameter the spec declares `fixed` (not a constructor argument).
    E0204,
    /// The same parameter overridden twice (`--set a=1 --set a=2`).
    E0205,
    /// The model file does not exist or cannot be read.
    E0301,
    /// The model file is not well-formed MJCF.
    E0302,
    /// A name (body, joint, site, ...) that the model does not have.
    E0303,
    /// An index outside the bounds of a model array.
    E0304,
    /// A selector expression that does not parse.
    E0401,
    /// An unknown data field in a selector.
    E0402,
    /// Sizes that do not fit together (e.g. `minus` of another length).
    E0403,
    /// The reward `sum` does not use every term exactly once.
    E0501,
    /// An info entry reports a reward term that does not exist or is switched off.
    E0502,
    /// The spec file itself cannot be read.
    E0600,
    /// No bundled id of that name, and no such spec file.
    E0601,
    /// The command cannot serve this kind of spec (e.g. `collect` on a multi-agent spec).
    E0602,
    /// A user's spec declares an id that is bundled, or registered from another file.
    E0603,
    /// Maze rows of different lengths.
    E0701,
    /// An unknown maze cell character.
    E0702,
    /// A maze with no goal cell (after the reference's fallbacks).
    E0703,
    /// A maze with no reset cell (after the reference's fallbacks).
    E0704,
    /// A maze goal cell no reset cell can reach.
    E0705,
    /// A maze robot wider than a cell.
    E0706,
    /// A maze robot whose root x, y are not `qpos[0:2]`.
    E0707,
    /// A maze reset option naming a wall or a cell outside the map.
    E0708,
    /// A goal term's `achieved` and `desired` have different lengths.
    E0801,
    /// An unknown `norm` option of a goal term.
    E0802,
    /// A goal threshold that is not a finite number ≥ 0.
    E0803,
    /// A goal term's `achieved` selects no element.
    E0804,
    /// `envc diff` of two different kinds of spec (task, multi-agent, maze).
    E0905,
    /// MuJoCo failed to compile the model.
    E1001,
    /// The compiled model disagrees with what the spec resolved from the MJCF.
    E1002,
    /// The compiled model holds values envc cannot run: a control range that is not finite, a
    /// non-finite or out-of-bounds position.
    E1003,
    /// MuJoCo raised an error (`mju_error`) while stepping or resetting, e.g. its arena overflowed.
    E1004,
    /// An action of the wrong length.
    E1101,
    /// A geom an event names is not in the compiled model (the MJCF reader and MuJoCo disagree).
    E1120,
    /// An action with a NaN or infinite entry.
    E1102,
    /// `step` before the first `reset`.
    E1103,
    /// A reset whose `resample_until` condition was not met within `limits::MAX_RESAMPLE_DRAWS`.
    E1104,
    /// An argument of a Python call of the wrong type or out of range (a seed, reset options,
    /// `num_envs`, `episodes`).
    E1105,
    /// `[actions]` gains on a model whose actuators are not position servos, or a keyframe or
    /// geom envspec found but the compiled model lacks.
    E1110,
    /// An unknown numerics profile name.
    E1301,
    /// `auto` numerics under CPU-feature settings numpy itself refuses to import with.
    E1302,
    /// A command that would never end on an env without a time limit: it needs `--max-steps`.
    E1401,
    /// A rollout whose trajectory would exceed `limits::MAX_TRAJECTORY_BYTES` in memory.
    E1402,
    /// A vector env whose envs would need more memory than the process can have.
    E1403,
    /// An actions `.npy` file that cannot be read, is truncated, or is not a 2-D float array.
    E1430,
    // Rendering (envspec::camera and the runtime's renderer).
    /// No usable EGL / OpenGL library (headless rendering needs Mesa's EGL).
    E1501,
    /// EGL is there but gives no headless display or context.
    E1502,
    /// A rendering camera or tracked body the model does not have.
    E1503,
    /// An unknown render mode.
    E1504,
    /// A rendering setting out of range or of the wrong form.
    E1505,
    /// A video or frame file could not be written (encoder missing or failed).
    E1506,
    /// MuJoCo's renderer raised an error (e.g. an offscreen buffer it cannot allocate).
    E1507,
    /// Warning: `minus` pairs elements of different joints (e.g. `qpos[7:] − default_pose` with
    /// the actuators in another order than the joints).
    W0401,
    /// Warning: an added body that falls under gravity with nothing holding it (a vertical
    /// slide joint, no contact geom, no gravity compensation): a goal marker that would drop.
    W0170,
    /// Warning: a reset draw that moves a position (a slide joint, a free joint's position, the
    /// goal vector) more than 10 m: centimetres written for metres.
    W0171,
    /// An `[end_effector]` or `[init] mocap` body that is not a mocap body of the compiled model,
    /// or (for `[end_effector]`) one no weld constraint ties to a robot body.
    E1111,
    /// A dataset spec (`specs/datasets/**.toml`) that cannot be read: not TOML, an unknown or
    /// missing key, a wrong type, no budget or both, an unknown format.
    E1801,
    /// An internal failure (a bug in envc) caught at the Python boundary.
    E1900,
}

impl fmt::Display for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self, f)
    }
}

/// One problem found in a spec, a model or an override.
#[derive(Clone, Debug)]
pub struct Diagnostic {
    /// The stable code (docs/errors.md).
    pub code: Code,
    /// One line saying what is wrong.
    pub message: String,
    /// Where, when the problem is in a file (overrides and I/O errors may have none).
    pub location: Option<Location>,
    /// What was expected, shown under the caret.
    pub label: Option<String>,
    /// A suggestion, e.g. "did you mean `healthy_reward`?".
    pub help: Option<String>,
}

impl Diagnostic {
    /// A diagnostic without location, label or help; add them with the builders below.
    pub fn new(code: Code, message: impl Into<String>) -> Self {
        Diagnostic {
            code,
            message: tidy(message.into()),
            location: None,
            label: None,
            help: None,
        }
    }
    /// Point the diagnostic at `location`.
    pub fn at(mut self, location: Location) -> Self {
        self.location = Some(location);
        self
    }
    /// Point it at `location` when there is one.
    pub fn at_opt(mut self, location: Option<Location>) -> Self {
        self.location = location;
        self
    }
    /// Say what was expected, under the caret.
    pub fn label(mut self, label: impl Into<String>) -> Self {
        self.label = Some(tidy(label.into()));
        self
    }
    /// Add a suggestion.
    pub fn help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(tidy(help.into()));
        self
    }
    /// Add a suggestion when there is one.
    pub fn help_opt(mut self, help: Option<String>) -> Self {
        if let Some(h) = help {
            self.help = Some(tidy(h));
        }
        self
    }

    /// `path:line:col` when the diagnostic has a location.
    pub fn position(&self) -> Option<String> {
        self.location.as_ref().map(Location::position)
    }

    /// The diagnostic as a warning (`warning[W0401]: …`): the spec is accepted.
    pub fn warning_text(&self) -> String {
        let s = self.to_string();
        match s.strip_prefix("error") {
            Some(rest) => format!("warning{rest}"),
            None => s,
        }
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "error[{}]: {}", self.code, self.message)?;
        if let Some(loc) = &self.location {
            let (line, col) = loc.file.line_col(loc.span.start);
            let text = loc.file.line_text(line);
            let gutter = line.to_string().len();
            let pad = " ".repeat(gutter);
            writeln!(f, "{pad}--> {}", loc.position())?;
            writeln!(f, "{pad} |")?;
            let line_end = loc
                .file
                .line_starts
                .get(line)
                .copied()
                .unwrap_or(loc.file.text.len());
            let end = loc.span.end.min(line_end).max(loc.span.start);
            let width = loc.file.text[loc.span.start..end]
                .trim_end()
                .chars()
                .count()
                .max(1);
            let (shown, lead, carets) = snippet(text, col - 1, width);
            writeln!(f, "{line} | {shown}")?;
            write!(f, "{pad} | {lead}{}", "^".repeat(carets))?;
            match &self.label {
                Some(label) => writeln!(f, " {label}")?,
                None => writeln!(f)?,
            }
        } else if let Some(label) = &self.label {
            writeln!(f, "  = note: {label}")?;
        }
        if let Some(help) = &self.help {
            let pad = match &self.location {
                Some(loc) => " ".repeat(loc.file.line_col(loc.span.start).0.to_string().len()),
                None => " ".into(),
            };
            writeln!(f, "{pad} = help: {help}")?;
        }
        Ok(())
    }
}

/// Characters never echoed raw: bidi overrides, embeddings, isolates and marks (they reorder what
/// a terminal shows, "Trojan Source") and C0/C1 controls other than tab and newline (they move
/// the cursor or recolour the terminal).
fn is_hidden(c: char) -> bool {
    matches!(c,
        '\u{0}'..='\u{8}' | '\u{b}'..='\u{1f}' | '\u{7f}'..='\u{9f}'
        | '\u{61c}' | '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// `s` with every hidden character written as a Rust escape (`\u{202e}`), so what a user reads
/// is what the file holds.
pub fn escape(s: &str) -> std::borrow::Cow<'_, str> {
    if !s.chars().any(is_hidden) {
        return s.into();
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if is_hidden(c) {
            out.push_str(&c.escape_unicode().to_string());
        } else {
            out.push(c);
        }
    }
    out.into()
}

/// Longest message, label or help text kept (in characters): a name or value taken from the
/// input can be megabytes long, and is clipped rather than echoed whole.
const MAX_TEXT: usize = 400;
/// Characters of a source line shown around the caret.
const WINDOW: usize = 120;

/// Escaped and clipped text of a message, label or help.
fn tidy(s: String) -> String {
    let s = match escape(&s) {
        std::borrow::Cow::Borrowed(_) => s,
        std::borrow::Cow::Owned(e) => e,
    };
    match s.char_indices().nth(MAX_TEXT) {
        Some((cut, _)) => {
            let rest = s[cut..].chars().count();
            format!("{}… ({rest} more characters)", &s[..cut])
        }
        None => s,
    }
}

/// The source line as shown under a diagnostic: at most [`WINDOW`] characters around the
/// caret (`…` where clipped), hidden characters escaped. `col` is the 0-based character column
/// of the span, `width` its length in characters. Returns the shown text, the blank lead before
/// the caret (tabs kept, so it lines up) and the caret count.
fn snippet(text: &str, col: usize, width: usize) -> (String, String, usize) {
    let chars: Vec<char> = text.chars().collect();
    let n = chars.len();
    let (start, end) = if n <= WINDOW {
        (0, n)
    } else {
        // The caret sits a third into the window, or the window ends at the line's end.
        let start = col.saturating_sub(WINDOW / 3).min(n - WINDOW);
        (start, start + WINDOW)
    };
    let col = col.clamp(start, end);
    let (mut shown, mut lead) = (String::new(), String::new());
    if start > 0 {
        shown.push('…');
        lead.push(' ');
    }
    let mut carets = 0;
    for (i, &c) in chars.iter().enumerate().take(end).skip(start) {
        let e = if is_hidden(c) {
            c.escape_unicode().to_string()
        } else {
            c.to_string()
        };
        let w = e.chars().count();
        if i < col {
            lead.push_str(&if c == '\t' {
                "\t".into()
            } else {
                " ".repeat(w)
            });
        } else if i < col + width {
            carets += w;
        }
        shown.push_str(&e);
    }
    if end < n {
        shown.push('…');
    }
    (shown, lead, carets.max(1))
}

/// Every diagnostic found in one pass (a spec reports all its errors at once).
#[derive(Clone, Debug, Default)]
pub struct Diagnostics(pub Vec<Diagnostic>);

impl Diagnostics {
    /// Record one more problem.
    pub fn push(&mut self, d: Diagnostic) {
        self.0.push(d);
    }
    /// Whether nothing was reported.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
    /// How many problems were reported.
    pub fn len(&self) -> usize {
        self.0.len()
    }
    /// The problems, in the order found.
    pub fn iter(&self) -> impl Iterator<Item = &Diagnostic> {
        self.0.iter()
    }
    /// Their codes, in order (what tests compare).
    pub fn codes(&self) -> Vec<Code> {
        self.0.iter().map(|d| d.code).collect()
    }
    /// Ok(value) when nothing was reported.
    pub fn into_result<T>(self, value: T) -> Result<T, Diagnostics> {
        if self.0.is_empty() {
            Ok(value)
        } else {
            Err(self)
        }
    }
}

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, d) in self.0.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{d}")?;
        }
        let n = self.0.len();
        write!(f, "\n{n} error{} found", if n == 1 { "" } else { "s" })
    }
}

impl std::error::Error for Diagnostics {}

impl From<Diagnostic> for Diagnostics {
    fn from(d: Diagnostic) -> Self {
        Diagnostics(vec![d])
    }
}

/// The closest candidate to `name` (by Jaro-Winkler similarity), as a "did you mean" help text.
pub fn suggest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<String> {
    let mut best: Vec<(f64, &str)> = vec![];
    for c in candidates {
        let score = strsim::jaro_winkler(name, c);
        if score <= 0.8 || best.iter().any(|(_, b)| *b == c) {
            continue;
        }
        match best.first() {
            Some((s, _)) if score > *s => best = vec![(score, c)],
            Some((s, _)) if score == *s => best.push((score, c)),
            None => best.push((score, c)),
            _ => {}
        }
    }
    // Names equally close are all offered: picking one would be a guess.
    match best.as_slice() {
        [] => None,
        [(_, c)] => Some(format!("did you mean `{c}`?")),
        many => Some(format!(
            "did you mean one of {}?",
            many.iter()
                .map(|(_, c)| format!("`{c}`"))
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// Display helper for paths in messages.
pub fn show_path(p: &Path) -> String {
    p.display().to_string()
}
