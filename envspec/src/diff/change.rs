//! One reported change: an instance of a rule, with what changed, "was X, now Y", where, and a
//! witness of the effect.

use serde::Serialize;
use serde::ser::SerializeStruct;

use super::rules::{Category, RuleId};

/// A file position, `path:line`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Pos {
    /// The file as the report names it.
    pub file: String,
    /// 1-based line.
    pub line: usize,
}

impl std::fmt::Display for Pos {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}", self.file, self.line)
    }
}

/// One reported change: an instance of a rule, with before, after, where and its effect.
#[derive(Clone, Debug)]
pub struct Change {
    /// The rule this change is an instance of; it decides the category.
    pub rule: RuleId,
    /// What changed, e.g. `reward.healthy`, `observation`, `param ctrl_cost_weight`.
    pub subject: String,
    /// What about it, e.g. `weight`, `added`, `removed`, `renamed`.
    pub aspect: String,
    /// The old value, None when the subject was added.
    pub was: Option<String>,
    /// The new value, None when the subject was removed.
    pub now: Option<String>,
    /// Where the old value was written.
    pub old_at: Option<Pos>,
    /// Where the new value is written (annotations point here).
    pub new_at: Option<Pos>,
    /// Evidence of the effect, e.g. `obs dim 27 → 105; cfrc_ext[0:78] added at index 27`.
    pub witness: Option<String>,
    /// Alters behaviour (results, policies or constructor calls); false: a compatible change.
    /// The rule's default, lowered where the rule says the resolved spec shows no effect.
    pub breaking: bool,
}

impl Change {
    /// A change of `rule`, breaking as the rule says by default.
    pub fn new(rule: RuleId, subject: impl Into<String>, aspect: impl Into<String>) -> Change {
        Change {
            rule,
            subject: subject.into(),
            aspect: aspect.into(),
            was: None,
            now: None,
            old_at: None,
            new_at: None,
            witness: None,
            breaking: rule.rule().breaking,
        }
    }
    /// The category its rule belongs to (it orders the report).
    pub fn category(&self) -> Category {
        self.rule.category()
    }
    /// Set the old and new values.
    pub fn values(mut self, was: Option<String>, now: Option<String>) -> Change {
        self.was = was;
        self.now = now;
        self
    }
    /// Set where the old and new values are written.
    pub fn at(mut self, old_at: Option<Pos>, new_at: Option<Pos>) -> Change {
        self.old_at = old_at;
        self.new_at = new_at;
        self
    }
    /// Add evidence of the effect.
    pub fn witness(mut self, w: impl Into<String>) -> Change {
        self.witness = Some(w.into());
        self
    }
    /// Override the rule's default breaking flag.
    pub fn breaking(mut self, b: bool) -> Change {
        self.breaking = b;
        self
    }
}

impl Serialize for Change {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("Change", 10)?;
        st.serialize_field("rule", &self.rule)?;
        st.serialize_field("category", &self.category())?;
        st.serialize_field("subject", &self.subject)?;
        st.serialize_field("aspect", &self.aspect)?;
        st.serialize_field("was", &self.was)?;
        st.serialize_field("now", &self.now)?;
        st.serialize_field("old_at", &self.old_at)?;
        st.serialize_field("new_at", &self.new_at)?;
        st.serialize_field("witness", &self.witness)?;
        st.serialize_field("breaking", &self.breaking)?;
        st.end()
    }
}
