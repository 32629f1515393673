//! A diff report (changes ordered by category, flags, verdict) and its text, Markdown, JSON and
//! GitHub-annotation renderings. Every change line carries its rule id (docs/diff-rules.md).

use std::fmt::Write;

use serde::Serialize;

use super::change::{Change, Pos};
use super::rules::{Category, RuleId};

/// What `envc diff` reports: the changes between two specs, ordered by category, and flags.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// Env id of the old spec.
    pub old_id: String,
    /// Env id of the new spec.
    pub new_id: String,
    /// The old spec's file as given (a `REV:path` included).
    pub old_file: String,
    /// The new spec's file as given.
    pub new_file: String,
    /// Every change, ordered by category.
    pub changes: Vec<Change>,
    /// Problems with the change itself, e.g. a policy-breaking change without a version bump.
    pub flags: Vec<String>,
}

/// The overall verdict of a diff; `envc diff` turns it into its exit status
/// (`cli/src/commands/diff.rs`, docs/diff-rules.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Nothing changed.
    NoChange,
    /// Only compatible changes.
    Compatible,
    /// Some change breaks results or policies, or a flag was raised.
    Breaking,
}

impl Report {
    /// An empty report between two files.
    pub fn new(
        old_id: impl Into<String>,
        new_id: impl Into<String>,
        old_file: impl Into<String>,
        new_file: impl Into<String>,
    ) -> Report {
        Report {
            old_id: old_id.into(),
            new_id: new_id.into(),
            old_file: old_file.into(),
            new_file: new_file.into(),
            changes: vec![],
            flags: vec![],
        }
    }

    /// Add changes (e.g. compiled-model differences found by the runtime), keeping the report
    /// ordered by category and its flags up to date.
    pub fn extend(&mut self, more: Vec<Change>) {
        self.changes.extend(more);
        self.changes.sort_by_key(|c| c.category());
        self.flags.clear();
        let breaks_policies = self.changes.iter().any(|c| {
            c.breaking && matches!(c.category(), Category::Observation | Category::Action)
        });
        // Results that change under the same id: a reviewer's signal to bump the version, as
        // Gymnasium bumps ids for reward, termination and physics fixes too (v4 → v5).
        let mut alters: Vec<&str> = self
            .changes
            .iter()
            .filter(|c| c.breaking)
            .filter_map(|c| match c.category() {
                Category::Reward => Some("reward"),
                Category::Termination => Some("episode endings"),
                Category::Reset => Some("initial states"),
                Category::Randomization => Some("training distribution"),
                Category::Dynamics => Some("dynamics"),
                _ => None,
            })
            .collect();
        alters.dedup();
        if self.old_id == self.new_id {
            if breaks_policies {
                self.flags.push(format!(
                    "this change breaks trained policies but the env id stays `{}`: bump its version",
                    self.new_id
                ));
            } else if !alters.is_empty() {
                self.flags.push(format!(
                    "this change alters results ({}: returns are not comparable) but the env id stays `{}`: bump its version",
                    alters.join(", "),
                    self.new_id
                ));
            }
        }
    }

    /// Breaking if any change breaks or any flag is raised, else compatible, or no change.
    pub fn verdict(&self) -> Verdict {
        let counted = self
            .changes
            .iter()
            .filter(|c| c.rule != RuleId::SelectorRespelled)
            .count();
        if counted == 0 && self.flags.is_empty() {
            Verdict::NoChange
        } else if self.changes.iter().any(|c| c.breaking) || !self.flags.is_empty() {
            Verdict::Breaking
        } else {
            Verdict::Compatible
        }
    }

    fn verdict_line(&self) -> String {
        let mut hurt: Vec<Category> = self
            .changes
            .iter()
            .filter(|c| c.breaking)
            .map(|c| c.category())
            .collect();
        hurt.sort();
        hurt.dedup();
        match self.verdict() {
            Verdict::NoChange => "no change".into(),
            Verdict::Compatible => "compatible (no behaviour change)".into(),
            Verdict::Breaking => format!(
                "BREAKING: {}",
                hurt.iter()
                    .map(|c| format!("{} ({})", c.title(), c.impact()))
                    .collect::<Vec<_>>()
                    .join("; ")
            ),
        }
    }

    /// `subject: aspect: was X, now Y` (without mark or rule id).
    fn body(c: &Change) -> String {
        let show = |v: &Option<String>, p: &Option<Pos>| match (v, p) {
            (Some(v), Some(p)) => format!("{v} ({p})"),
            (Some(v), None) => v.clone(),
            (None, Some(p)) => format!("absent ({p})"),
            (None, None) => "absent".into(),
        };
        let body = match c.aspect.as_str() {
            "added" => format!("added: {}", show(&c.now, &c.new_at)),
            "removed" => format!("removed: was {}", show(&c.was, &c.old_at)),
            _ => format!(
                "{}: was {}, now {}",
                c.aspect,
                show(&c.was, &c.old_at),
                show(&c.now, &c.new_at)
            ),
        };
        format!("{}: {body}", c.subject)
    }

    /// The terminal report: changes by category, each with its rule id, then flags and the verdict.
    pub fn to_text(&self) -> String {
        let mut o = String::new();
        let _ = writeln!(
            o,
            "envc diff: {} ({}) → {} ({})",
            self.old_id, self.old_file, self.new_id, self.new_file
        );
        let _ = writeln!(o, "verdict: {}", self.verdict_line());
        for f in &self.flags {
            let _ = writeln!(o, "flag: {f}");
        }
        let mut cat = None;
        for c in &self.changes {
            if cat != Some(c.category()) {
                cat = Some(c.category());
                let _ = writeln!(o, "\n{} — {}", c.category().title(), c.category().impact());
            }
            let mark = if c.breaking { "!" } else { " " };
            let _ = writeln!(o, "  {mark} [{}] {}", c.rule.id(), Self::body(c));
            if let Some(w) = &c.witness {
                let _ = writeln!(o, "      {w}");
            }
        }
        if !self.changes.is_empty() {
            let _ = writeln!(o, "\n(! marks changes that alter behaviour)");
        }
        o
    }

    /// The report as a Markdown table per category (for pull-request comments).
    pub fn to_markdown(&self) -> String {
        let esc = |s: &str| s.replace('|', "\\|");
        let mut o = String::new();
        let _ = writeln!(o, "### `envc diff` {} → {}\n", self.old_id, self.new_id);
        let _ = writeln!(o, "**Verdict:** {}\n", self.verdict_line());
        for f in &self.flags {
            let _ = writeln!(o, "> **Warning:** {f}\n");
        }
        let mut cat = None;
        for c in &self.changes {
            if cat != Some(c.category()) {
                cat = Some(c.category());
                let _ = writeln!(
                    o,
                    "\n#### {} — {}\n",
                    c.category().title(),
                    c.category().impact()
                );
                let _ = writeln!(
                    o,
                    "| | rule | what | was | now | note |\n|---|---|---|---|---|---|"
                );
            }
            let cell = |v: &Option<String>, p: &Option<Pos>| {
                let v = v
                    .as_deref()
                    .map(|v| code_span(&esc(v)))
                    .unwrap_or_else(|| "—".into());
                match p {
                    Some(p) => format!("{v} <sub>{p}</sub>"),
                    None => v,
                }
            };
            let _ = writeln!(
                o,
                "| {} | `{}` | {} {} | {} | {} | {} |",
                if c.breaking { "⚠️" } else { "" },
                c.rule.id(),
                esc(&c.subject),
                esc(&c.aspect),
                cell(&c.was, &c.old_at),
                cell(&c.now, &c.new_at),
                esc(c.witness.as_deref().unwrap_or(""))
            );
        }
        o
    }

    /// The report as JSON, every change with its rule, values and positions.
    pub fn to_json(&self) -> String {
        let v = serde_json::json!({
            "old": {"id": self.old_id, "file": self.old_file},
            "new": {"id": self.new_id, "file": self.new_file},
            "verdict": self.verdict(),
            "flags": self.flags,
            "changes": self.changes,
        });
        serde_json::to_string_pretty(&v).unwrap_or_default()
    }

    /// GitHub Actions workflow commands: annotations on the new spec's lines.
    pub fn to_github(&self) -> String {
        let mut o = String::new();
        let esc = |s: &str| {
            s.replace('%', "%25")
                .replace('\r', "%0D")
                .replace('\n', "%0A")
        };
        for f in &self.flags {
            let _ = writeln!(
                o,
                "::error file={},title=envc diff::{}",
                self.new_file,
                esc(f)
            );
        }
        for c in &self.changes {
            let level = if c.breaking {
                "error"
            } else if c.category() == Category::Documentation {
                "notice"
            } else {
                "warning"
            };
            let at = c.new_at.as_ref().or(c.old_at.as_ref());
            let loc = at
                .map(|p| format!(" file={},line={}", p.file, p.line))
                .unwrap_or_else(|| format!(" file={}", self.new_file));
            let mut msg = format!("[{}] {}", c.rule.id(), Self::body(c));
            if let Some(w) = &c.witness {
                msg.push_str(&format!(" — {w}"));
            }
            let _ = writeln!(
                o,
                "::{level}{loc},title=envc diff: {}::{}",
                c.category().title(),
                esc(&msg)
            );
        }
        o
    }
}

/// A Markdown code span of any text: the fence is one backtick longer than the longest run of
/// backticks inside (CommonMark), padded when the text starts or ends with one, so a value such
/// such as one naming a reward term in backticks does not break the table.
fn code_span(text: &str) -> String {
    let longest = text.split(|c| c != '`').map(str::len).max().unwrap_or(0);
    let fence = "`".repeat(longest + 1);
    let pad = if text.starts_with('`') || text.ends_with('`') {
        " "
    } else {
        ""
    };
    format!("{fence}{pad}{text}{pad}{fence}")
}

#[cfg(test)]
mod code_span_tests {
    use super::code_span;

    #[test]
    fn backticks_inside_get_a_longer_fence() {
        assert_eq!(code_span("0.5"), "`0.5`");
        assert_eq!(
            code_span("reward term `alive`"),
            "`` reward term `alive` ``"
        );
        assert_eq!(code_span("a``b"), "```a``b```");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(old_id: &str, new_id: &str, changes: Vec<Change>) -> Report {
        let mut r = Report::new(old_id, new_id, "old.toml", "new.toml");
        r.extend(changes);
        r
    }

    #[test]
    fn verdicts() {
        assert_eq!(report("A-v1", "A-v1", vec![]).verdict(), Verdict::NoChange);
        // docs/diff-rules.md: a respelled selector is "shown, but no change (the verdict ignores it)".
        let respelled = Change::new(RuleId::SelectorRespelled, "observation.x", "source");
        assert!(!respelled.breaking);
        assert_eq!(
            report("A-v1", "A-v1", vec![respelled.clone()]).verdict(),
            Verdict::NoChange
        );
        // param-added is "no" in the table: compatible, no flag.
        let added = Change::new(RuleId::ParamAdded, "param x", "added");
        let r = report("A-v1", "A-v1", vec![respelled, added.clone()]);
        assert_eq!((r.verdict(), r.flags.len()), (Verdict::Compatible, 0));
        // A breaking-by-default rule lowered where the resolved spec shows no effect.
        let lowered =
            Change::new(RuleId::RewardTermKeyChanged, "reward.a", "weight").breaking(false);
        assert_eq!(
            report("A-v1", "A-v1", vec![lowered]).verdict(),
            Verdict::Compatible
        );
        let layout = Change::new(RuleId::ObservationLayoutChanged, "observation", "layout");
        assert!(layout.breaking);
        assert_eq!(
            report("A-v1", "A-v2", vec![added, layout]).verdict(),
            Verdict::Breaking
        );
    }

    #[test]
    fn a_breaking_change_under_the_same_id_is_flagged() {
        let layout = Change::new(RuleId::ObservationLayoutChanged, "observation", "layout");
        let r = report("Hopper-v5", "Hopper-v5", vec![layout.clone()]);
        assert_eq!(
            r.flags,
            [
                "this change breaks trained policies but the env id stays `Hopper-v5`: bump its version"
            ]
        );
        // A new id is the announcement: no flag, still breaking.
        let r = report("Hopper-v4", "Hopper-v5", vec![layout]);
        assert!(r.flags.is_empty());
        assert_eq!(r.verdict(), Verdict::Breaking);
        // Results change (reward, dynamics) without touching the policy's interface.
        let r = report(
            "Hopper-v5",
            "Hopper-v5",
            vec![
                Change::new(RuleId::ModelArrayChanged, "model", "body_mass"),
                Change::new(RuleId::RewardTermKeyChanged, "reward.a", "weight"),
            ],
        );
        assert_eq!(
            r.flags,
            [
                "this change alters results (reward, dynamics: returns are not comparable) but the env id stays `Hopper-v5`: bump its version"
            ]
        );
        // Only a parameter-category break (a removed parameter) flags nothing.
        let r = report(
            "A-v1",
            "A-v1",
            vec![Change::new(RuleId::ParamRemoved, "param x", "removed")],
        );
        assert_eq!((r.verdict(), r.flags.len()), (Verdict::Breaking, 0));
    }

    #[test]
    fn changes_are_ordered_by_category_most_harmful_first() {
        let r = report(
            "A-v1",
            "A-v2",
            vec![
                Change::new(RuleId::DocChanged, "reward.a", "doc"),
                Change::new(RuleId::InfoKeyAdded, "info.k", "added"),
                Change::new(RuleId::ActionsRemoved, "actions", "removed"),
                Change::new(RuleId::RewardSumChanged, "reward", "sum"),
                Change::new(RuleId::NoiseAdded, "observation.x", "noise"),
            ],
        );
        let order: Vec<&str> = r.changes.iter().map(|c| c.category().key()).collect();
        assert_eq!(
            order,
            ["action", "reward", "randomization", "info", "documentation"]
        );
    }

    #[test]
    fn text_lines_as_the_docs_show_them() {
        // The example in docs/diff-rules.md, rebuilt.
        let pos = |file: &str, line| {
            Some(Pos {
                file: file.into(),
                line,
            })
        };
        let c = Change::new(
            RuleId::RewardTermKeyChanged,
            "reward.healthy",
            "paid_when_unhealthy",
        )
        .values(Some("\"terminate_when_unhealthy\"".into()), None)
        .at(
            pos("specs/gymnasium/hopper_v4.toml", 47),
            pos("specs/gymnasium/hopper.toml", 46),
        );
        let text = report("Hopper-v4", "Hopper-v5", vec![c]).to_text();
        assert!(
            text.contains(
                "\nreward — returns are no longer comparable\n  ! [reward-term-key-changed] reward.healthy: paid_when_unhealthy: was \"terminate_when_unhealthy\" (specs/gymnasium/hopper_v4.toml:47), now absent (specs/gymnasium/hopper.toml:46)\n"
            ),
            "{text}"
        );
        assert!(text.contains("verdict: BREAKING: reward (returns are no longer comparable)\n"));
        let added =
            Change::new(RuleId::ParamAdded, "param x", "added").values(None, Some("1".into()));
        let text = report("A-v1", "A-v1", vec![added]).to_text();
        assert!(
            text.contains("verdict: compatible (no behaviour change)\n"),
            "{text}"
        );
        assert!(
            text.contains("    [param-added] param x: added: 1\n"),
            "{text}"
        );
    }
}
