//! What the tables of `bad_input.rs` stand on: the spec their cases break (`MINI`), what a row
//! says (`Case`, `Want`), the `cases!` macro that makes each row a `#[test]`, and `run`, which
//! loads a row's spec and checks what came out.

use std::path::{Path, PathBuf};

use envspec::{Code, Diagnostic, Diagnostics, Override, ResolvedSpec, Spec, load};

pub(super) use {Base::*, Expect::*, Stage::*};

/// `<repo>/assets/gymnasium`, absolute.
pub(super) fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace root")
        .join("assets/gymnasium")
}

/// A per-test scratch directory under the system temp dir, removed when dropped.
pub(super) struct Scratch(pub(super) PathBuf);

impl Scratch {
    pub(super) fn new(test: &str) -> Scratch {
        let dir =
            std::env::temp_dir().join(format!("envspec-bad-input-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create scratch dir");
        Scratch(dir)
    }
    pub(super) fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.0.join(name);
        std::fs::write(&p, text).expect("write scratch file");
        p
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A small Hopper spec; every case of `bad_input.rs` breaks one or more of its lines, so its
/// line numbers matter.
pub(super) const MINI: &str = r#"[env]
id = "Mini-v0"

[params]
xml_file = 'ASSETS/hopper.xml'
frame_skip = 4
max_episode_steps = 1000
ctrl_cost_weight = 1e-3
healthy_reward = 1.0
healthy_z_range = [0.7, inf]
terminate_when_unhealthy = true

[observation.qpos]
source = "qpos[1:]"

[observation.qvel]
source = "qvel"
clip = [-10.0, 10.0]

[reward]
sum = [["forward", "healthy"], "ctrl"]

[reward.forward]
kind = "velocity"
source = "qpos[0]"

[reward.healthy]
kind = "healthy"
weight = "healthy_reward"

[reward.ctrl]
kind = "sum_squares"
source = "action"
weight = "ctrl_cost_weight"
cost = true

[health]
terminate = "terminate_when_unhealthy"

[health.height]
kind = "in_range"
source = "qpos[1]"
range = "healthy_z_range"

[reset.qpos]
target = "qpos"
kind = "uniform"
scale = 5e-3

[info.x_position]
source = "qpos[0]"
"#;

/// Lines of `MINI` that several cases edit (`ASSETS` as in `Case`).
pub(super) const HEIGHT: &str = "source = \"qpos[1]\"";
pub(super) const HEALTH_CHECK: &str =
    "kind = \"in_range\"\nsource = \"qpos[1]\"\nrange = \"healthy_z_range\"";
pub(super) const FORWARD: &str = "source = \"qpos[0]\"\n\n[reward.healthy]";
pub(super) const SUM: &str = "sum = [[\"forward\", \"healthy\"], \"ctrl\"]";
pub(super) const XML_FILE: &str = "'ASSETS/hopper.xml'";

pub(super) fn mini() -> String {
    MINI.replace("ASSETS", &assets().display().to_string())
}

/// `text` with the single occurrence of `from` replaced by `to`.
pub(super) fn with(text: &str, from: &str, to: &str) -> String {
    assert_eq!(
        text.matches(from).count(),
        1,
        "`{from}` must occur exactly once in the spec"
    );
    text.replacen(from, to, 1)
}

/// A real bundled spec, with its model path made absolute so it can live in a scratch dir.
fn real(file: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../specs/gymnasium")
        .join(file);
    let text = std::fs::read_to_string(&path).expect("bundled spec");
    text.replace(
        "\"../../assets/gymnasium/",
        &format!("\"{}/", assets().display()),
    )
}

/// `line:col` of a diagnostic (the part of `position()` after the file path).
pub(super) fn lc(d: &Diagnostic) -> String {
    let p = d
        .position()
        .unwrap_or_else(|| panic!("no position for {d}"));
    let mut parts = p.rsplitn(3, ':');
    let col = parts.next().expect("col");
    let line = parts.next().expect("line");
    format!("{line}:{col}")
}

/// The position of the first occurrence of `needle` in `text`, as `line:col` (col in characters).
pub(super) fn find_lc(text: &str, needle: &str) -> String {
    let at = text
        .find(needle)
        .unwrap_or_else(|| panic!("`{needle}` not in text"));
    let line = text[..at].matches('\n').count() + 1;
    let start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    format!("{line}:{}", text[start..at].chars().count() + 1)
}

/// One load of a spec and what must come of it. In every text of a case, `ASSETS` stands for the
/// bundled models' directory and `SCRATCH` for the test's scratch directory.
pub(super) struct Case {
    pub(super) base: Base,
    pub(super) stage: Stage,
    /// The spec's file name: in the scratch dir, or as given to `Spec::parse`.
    pub(super) file: &'static str,
    /// `(name, text)` written to the scratch dir first: model files.
    pub(super) files: &'static [(&'static str, &'static str)],
    /// `(from, to)` in order; each `from` must occur exactly once.
    pub(super) edits: &'static [(&'static str, &'static str)],
    /// Appended after the edits.
    pub(super) append: &'static str,
    /// `name=value`, as on the command line.
    pub(super) overrides: &'static [&'static str],
    pub(super) expect: Expect,
}

/// What a row leaves out: `MINI` unchanged, resolved as `spec.toml`.
pub(super) const LOAD: Case = Case {
    base: Mini,
    stage: Resolve,
    file: "spec.toml",
    files: &[],
    edits: &[],
    append: "",
    overrides: &[],
    expect: Fails(&[]),
};

/// The spec text before the edits.
pub(super) enum Base {
    /// `MINI`.
    Mini,
    /// A spec of `specs/gymnasium/`.
    Real(&'static str),
    Empty,
    /// No spec file at all.
    Absent,
}

pub(super) enum Stage {
    /// `envspec::load`: parse, then resolve against the model, with the overrides.
    Resolve,
    /// `Spec::load`: read and parse only.
    Read,
    /// `Spec::parse` of the text under the bare name `file`; nothing is written.
    Parse,
}

pub(super) enum Expect {
    /// Exactly these diagnostics, in this order.
    Fails(&'static [Want]),
    /// `Resolve` succeeds; the function checks the resolved spec.
    Resolves(fn(&ResolvedSpec)),
    /// `Parse` succeeds.
    Parses,
}

/// One expected diagnostic: its code, and whatever else the row asserts.
#[derive(Clone, Copy)]
pub(super) struct Want {
    code: Code,
    at: At,
    message: Text,
    help: Option<&'static str>,
    label: Option<&'static str>,
}

#[derive(Clone, Copy)]
enum At {
    Unchecked,
    /// `line:col`.
    Lc(&'static str),
    /// `line:col` of the first occurrence of this text in the spec.
    Of(&'static str),
    /// The whole `position()`, file included.
    Is(&'static str),
    /// No position: an override, or a file that cannot be read.
    Nowhere,
}

#[derive(Clone, Copy)]
enum Text {
    Unchecked,
    Is(&'static str),
    StartsWith(&'static str),
    EndsWith(&'static str),
}

/// A diagnostic with code `code`; the methods add what else it must say.
pub(super) const fn err(code: Code) -> Want {
    Want {
        code,
        at: At::Unchecked,
        message: Text::Unchecked,
        help: None,
        label: None,
    }
}

impl Want {
    pub(super) const fn at(mut self, lc: &'static str) -> Want {
        self.at = At::Lc(lc);
        self
    }
    pub(super) const fn at_text(mut self, needle: &'static str) -> Want {
        self.at = At::Of(needle);
        self
    }
    pub(super) const fn pos(mut self, position: &'static str) -> Want {
        self.at = At::Is(position);
        self
    }
    pub(super) const fn nowhere(mut self) -> Want {
        self.at = At::Nowhere;
        self
    }
    pub(super) const fn msg(mut self, message: &'static str) -> Want {
        self.message = Text::Is(message);
        self
    }
    pub(super) const fn msg_starts(mut self, start: &'static str) -> Want {
        self.message = Text::StartsWith(start);
        self
    }
    pub(super) const fn msg_ends(mut self, end: &'static str) -> Want {
        self.message = Text::EndsWith(end);
        self
    }
    pub(super) const fn help(mut self, help: &'static str) -> Want {
        self.help = Some(help);
        self
    }
    pub(super) const fn label(mut self, label: &'static str) -> Want {
        self.label = Some(label);
        self
    }
}

/// One `#[test]` per row `name { field: value, .. }`, the fields of a `Case` (the rest from
/// `LOAD`); a row of several `{ .. }` runs them in order.
macro_rules! cases {
    ($($(#[$doc:meta])* $name:ident $({ $($field:ident: $value:expr),* $(,)? })+)*) => {$(
        $(#[$doc])*
        #[test]
        fn $name() {
            const CASES: &[Case] = &[$(Case { $($field: $value,)* ..LOAD }),+];
            run(stringify!($name), CASES);
        }
    )*};
}
pub(super) use cases;

/// Loads each case in turn, in one scratch dir named after the test, and checks what came out.
pub(super) fn run(test: &str, cases: &[Case]) {
    let s = Scratch::new(test);
    let expand = |t: &str| {
        t.replace("ASSETS", &assets().display().to_string())
            .replace("SCRATCH", &s.0.display().to_string())
    };
    for (i, case) in cases.iter().enumerate() {
        let mut text = match case.base {
            Mini => mini(),
            Real(file) => real(file),
            Empty | Absent => String::new(),
        };
        for (from, to) in case.edits {
            text = with(&text, &expand(from), &expand(to));
        }
        text.push_str(case.append);
        for (name, body) in case.files {
            s.write(name, body);
        }
        let path = s.0.join(case.file);
        if !matches!(case.base, Absent) && !matches!(case.stage, Parse) {
            s.write(case.file, &text);
        }
        let overrides: Vec<Override> = case
            .overrides
            .iter()
            .map(|o| Override::parse(o).unwrap_or_else(|d| panic!("override `{o}`: {d}")))
            .collect();
        let loaded = match case.stage {
            Resolve => load(&path, &overrides).map(Some),
            Read => Spec::load(&path).map(|_| None),
            Parse => Spec::parse(Path::new(case.file), text.clone()).map(|_| None),
        };
        match (&case.expect, loaded) {
            (Fails(wants), Err(d)) => check(i, &d, wants, &text, &expand),
            (Resolves(verify), Ok(Some(spec))) => verify(&spec),
            (Parses, Ok(None)) => {}
            (Fails(_), Ok(spec)) => panic!(
                "case {i}: expected errors, but `{}` loaded",
                spec.map_or_else(|| case.file.to_string(), |r| r.id)
            ),
            (_, Err(d)) => panic!("case {i}: expected no errors, got\n{d}"),
            (_, Ok(_)) => panic!("case {i}: `Resolves` needs `Resolve`, `Parses` needs `Parse`"),
        }
    }
}

/// `d` is exactly the diagnostics of `wants`, each saying what its row asserts.
fn check(
    case: usize,
    d: &Diagnostics,
    wants: &[Want],
    text: &str,
    expand: &dyn Fn(&str) -> String,
) {
    let codes: Vec<Code> = wants.iter().map(|w| w.code).collect();
    assert_eq!(d.codes(), codes, "case {case}: {d}");
    // The summary line counts them too.
    let n = d.len();
    let count = format!("\n{n} error{} found", if n == 1 { "" } else { "s" });
    assert!(d.to_string().ends_with(&count), "case {case}: {d}");
    for (k, (got, want)) in d.iter().zip(wants).enumerate() {
        let ctx = format!("case {case}, diagnostic {k}:\n{got}");
        match want.at {
            At::Unchecked => {}
            At::Lc(at) => assert_eq!(lc(got), at, "{ctx}"),
            At::Of(needle) => assert_eq!(lc(got), find_lc(text, needle), "{ctx}"),
            At::Is(position) => assert_eq!(got.position(), Some(expand(position)), "{ctx}"),
            At::Nowhere => assert_eq!(got.position(), None, "{ctx}"),
        }
        match want.message {
            Text::Unchecked => {}
            Text::Is(m) => assert_eq!(got.message, expand(m), "{ctx}"),
            Text::StartsWith(m) => assert!(got.message.starts_with(&expand(m)), "{ctx}"),
            Text::EndsWith(m) => assert!(got.message.ends_with(&expand(m)), "{ctx}"),
        }
        if let Some(help) = want.help {
            assert_eq!(got.help.as_deref(), Some(expand(help).as_str()), "{ctx}");
        }
        if let Some(label) = want.label {
            assert_eq!(got.label.as_deref(), Some(expand(label).as_str()), "{ctx}");
        }
    }
}
