//! Semantic diff of two specs, for reviewers: what a change does to trained policies and to
//! published returns.
//!
//! Two levels are compared. The written spec (sections matched by name, renames detected, every
//! key "was X, now Y" with file:line on both sides) says *what* changed; the resolved specs under
//! default parameters say *whether it matters* (a weight rewritten as a parameter reference with
//! the same value is not a reward change) and give witnesses (observation indices, element names).
//! Compiled-model differences (dynamics) need MuJoCo; the runtime adds them to the report.

use std::fmt::Debug;
use std::fmt::Write;

use serde::Serialize;

use crate::describe;
use crate::ir::*;
use crate::syntax::{Section, Spec};
use crate::value::Val;

/// Who a change hurts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Category {
    Observation,
    Action,
    Reward,
    Termination,
    Reset,
    Dynamics,
    Parameters,
    Info,
    Documentation,
}

impl Category {
    pub fn title(self) -> &'static str {
        match self {
            Category::Observation => "observation layout",
            Category::Action => "action layout",
            Category::Reward => "reward",
            Category::Termination => "termination / episode",
            Category::Reset => "reset distribution",
            Category::Dynamics => "dynamics",
            Category::Parameters => "parameters",
            Category::Info => "info",
            Category::Documentation => "documentation only",
        }
    }
    /// Who it hurts when the change alters behaviour.
    pub fn impact(self) -> &'static str {
        match self {
            Category::Observation | Category::Action => "breaks trained policies",
            Category::Reward => "returns are no longer comparable",
            Category::Termination => "episode lengths and returns change",
            Category::Reset => "initial states change; returns are not comparable",
            Category::Dynamics => "the physics changes; trained policies and returns are affected",
            Category::Parameters => "constructor arguments change",
            Category::Info => "logged info changes",
            Category::Documentation => "no behaviour change",
        }
    }
}

/// A file position, `path:line`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Pos {
    pub file: String,
    pub line: usize,
}

impl std::fmt::Display for Pos {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}", self.file, self.line)
    }
}

#[derive(Clone, Debug, Serialize)]
pub struct Change {
    pub category: Category,
    /// What changed, e.g. `reward.healthy`, `observation`, `param ctrl_cost_weight`.
    pub subject: String,
    /// What about it, e.g. `weight`, `added`, `removed`, `renamed`.
    pub aspect: String,
    pub was: Option<String>,
    pub now: Option<String>,
    pub old_at: Option<Pos>,
    pub new_at: Option<Pos>,
    /// Evidence of the effect, e.g. `obs dim 27 → 105; cfrc_ext[0:78] added at index 27`.
    pub witness: Option<String>,
    /// Alters behaviour (results, policies or constructor calls); false: a compatible change.
    pub breaking: bool,
}

#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub old_id: String,
    pub new_id: String,
    pub old_file: String,
    pub new_file: String,
    pub changes: Vec<Change>,
    /// Problems with the change itself, e.g. a policy-breaking change without a version bump.
    pub flags: Vec<String>,
}

/// The overall verdict, also the exit status of `envc diff`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    NoChange,
    Compatible,
    Breaking,
}

impl Verdict {
    pub fn exit_code(self) -> u8 {
        match self {
            Verdict::NoChange => 0,
            Verdict::Compatible => 1,
            Verdict::Breaking => 3,
        }
    }
}

/// `Debug` of an IR value with what does not change behaviour removed: names, docs and how a
/// selector was spelled (`xpos[$main_body]` vs `xpos[torso]` select the same elements).
fn canon<T: Debug>(x: &T) -> String {
    let s = format!("{x:?}");
    let mut out = String::with_capacity(s.len());
    let mut rest = s.as_str();
    'outer: while !rest.is_empty() {
        for field in ["name: \"", "doc: \"", "text: \"", "key: \""] {
            if rest.starts_with(field) && (out.ends_with(' ') || out.ends_with('{')) {
                // Skip to the closing quote (Debug escapes inner quotes as \").
                let body = &rest[field.len()..];
                let mut end = 0;
                let bytes = body.as_bytes();
                while end < bytes.len()
                    && !(bytes[end] == b'"' && (end == 0 || bytes[end - 1] != b'\\'))
                {
                    end += 1;
                }
                rest = body.get(end + 1..).unwrap_or("");
                rest = rest.strip_prefix(", ").unwrap_or(rest);
                continue 'outer;
            }
        }
        let c = rest.chars().next().expect("non-empty");
        out.push(c);
        rest = &rest[c.len_utf8()..];
    }
    out
}

fn pos(spec: &Spec, loc: &crate::diagnostic::Location) -> Pos {
    let (line, _) = loc.file.line_col(loc.span.start);
    let _ = spec;
    Pos {
        file: loc.file.path.display().to_string(),
        line,
    }
}

struct Ctx<'a> {
    old: &'a Spec,
    new: &'a Spec,
    old_r: &'a ResolvedSpec,
    new_r: &'a ResolvedSpec,
    changes: Vec<Change>,
}

impl Ctx<'_> {
    #[allow(clippy::too_many_arguments)]
    fn push(
        &mut self,
        category: Category,
        subject: impl Into<String>,
        aspect: impl Into<String>,
        was: Option<String>,
        now: Option<String>,
        old_at: Option<Pos>,
        new_at: Option<Pos>,
        breaking: bool,
    ) {
        self.changes.push(Change {
            category,
            subject: subject.into(),
            aspect: aspect.into(),
            was,
            now,
            old_at,
            new_at,
            witness: None,
            breaking,
        });
    }
}

/// Diff two specs (each with its resolution under default parameters).
pub fn diff(old: &Spec, old_r: &ResolvedSpec, new: &Spec, new_r: &ResolvedSpec) -> Report {
    let mut cx = Ctx {
        old,
        new,
        old_r,
        new_r,
        changes: vec![],
    };
    env_section(&mut cx);
    params(&mut cx);
    observation(&mut cx);
    sections(
        &mut cx,
        Category::Reward,
        "reward",
        &old.reward,
        &new.reward,
        &|r: &ResolvedSpec, n: &str| {
            r.reward.iter().find(|t| t.name == n).map(|t| {
                canon(&RewardTerm {
                    info: None,
                    ..t.clone()
                })
            })
        },
    );
    reward_sum(&mut cx);
    sections(
        &mut cx,
        Category::Termination,
        "health",
        &old.health,
        &new.health,
        &|r: &ResolvedSpec, n: &str| r.health.iter().find(|c| c.name == n).map(canon),
    );
    episode(&mut cx);
    sections(
        &mut cx,
        Category::Reset,
        "reset",
        &old.reset,
        &new.reset,
        &|r: &ResolvedSpec, n: &str| r.reset.iter().find(|c| c.name == n).map(canon),
    );
    reset_order(&mut cx);
    info_items(&mut cx);

    let mut report = Report {
        old_id: old_r.id.clone(),
        new_id: new_r.id.clone(),
        old_file: old.path().display().to_string(),
        new_file: new.path().display().to_string(),
        changes: vec![],
        flags: vec![],
    };
    report.extend(cx.changes);
    report
}

fn info_canon(r: &ResolvedSpec, i: &InfoItem) -> String {
    match &i.kind {
        InfoKind::Term(t) => format!(
            "term {} {}",
            r.reward
                .get(*t)
                .map(|t| canon(&RewardTerm {
                    info: None,
                    ..t.clone()
                }))
                .unwrap_or_default(),
            i.unweighted
        ),
        _ => canon(&InfoItem {
            at_reset: false,
            ..i.clone()
        }),
    }
}

/// The reward term an info entry reports, if any.
fn info_term<'a>(r: &'a ResolvedSpec, i: &InfoItem) -> Option<&'a str> {
    match i.kind {
        InfoKind::Term(t) => r.reward.get(t).map(|t| t.name.as_str()),
        _ => None,
    }
}

fn env_section(cx: &mut Ctx) {
    let (o, n) = (cx.old, cx.new);
    if o.id != n.id {
        let (a, b) = (pos(o, &o.id_loc), pos(n, &n.id_loc));
        cx.push(
            Category::Documentation,
            "env",
            "id",
            Some(o.id.clone()),
            Some(n.id.clone()),
            Some(a),
            Some(b),
            false,
        );
    }
    if o.description != n.description {
        cx.push(
            Category::Documentation,
            "env",
            "description",
            Some(o.description.clone()),
            Some(n.description.clone()),
            None,
            None,
            false,
        );
    }
    if o.reward_threshold != n.reward_threshold {
        let f = |x: Option<f64>| x.map(|v| v.to_string()).unwrap_or_else(|| "none".into());
        cx.push(
            Category::Documentation,
            "env",
            "reward_threshold",
            Some(f(o.reward_threshold)),
            Some(f(n.reward_threshold)),
            None,
            None,
            false,
        );
    }
    if o.entry_point != n.entry_point {
        let f = |x: &Option<String>| x.clone().unwrap_or_else(|| "none".into());
        cx.push(
            Category::Documentation,
            "env",
            "entry_point",
            Some(f(&o.entry_point)),
            Some(f(&n.entry_point)),
            None,
            None,
            false,
        );
    }
}

/// The behavioural categories of the places a parameter is referenced from.
fn uses(spec: &Spec, param: &str) -> Vec<(Category, String)> {
    fn refers(v: &Val, p: &str) -> bool {
        match &v.kind {
            crate::value::ValKind::Str(s) => {
                let s = s.trim_start_matches('!');
                s == p || s.contains(&format!("${p}]"))
            }
            crate::value::ValKind::Array(a) => a.iter().any(|x| refers(x, p)),
            crate::value::ValKind::Table(t) => t.iter().any(|e| refers(&e.value, p)),
            _ => false,
        }
    }
    let mut out = vec![];
    let groups: [(&[Section], Category, &str); 5] = [
        (&spec.observation, Category::Observation, "observation"),
        (&spec.reward, Category::Reward, "reward"),
        (&spec.health, Category::Termination, "health"),
        (&spec.reset, Category::Reset, "reset"),
        (&spec.info, Category::Info, "info"),
    ];
    for (secs, cat, kind) in groups {
        for s in secs {
            if s.entries
                .iter()
                .any(|e| e.key != "doc" && refers(&e.value, param))
            {
                out.push((cat, format!("{kind}.{}", s.name)));
            }
        }
    }
    if spec
        .health_terminate
        .as_ref()
        .is_some_and(|v| refers(v, param))
    {
        out.push((Category::Termination, "health.terminate".into()));
    }
    match param {
        "xml_file" | "frame_skip" => {
            out.push((Category::Dynamics, format!("the built-in `{param}`")))
        }
        "max_episode_steps" => out.push((Category::Termination, "the time limit".into())),
        _ => {}
    }
    out
}

fn params(cx: &mut Ctx) {
    let (o, n) = (cx.old, cx.new);
    for p in &o.params {
        let at = Some(pos(o, &p.name_loc));
        match n.param(&p.name) {
            None => cx.push(
                Category::Parameters,
                format!("param {}", p.name),
                "removed",
                Some(p.default.to_toml()),
                None,
                at,
                None,
                true,
            ),
            Some(q) => {
                let new_at = Some(pos(n, &q.name_loc));
                if p.default.to_toml() != q.default.to_toml() {
                    let used = uses(n, &q.name);
                    let cat = used
                        .iter()
                        .map(|(c, _)| *c)
                        .min()
                        .unwrap_or(Category::Parameters);
                    let mut c = Change {
                        category: if used.is_empty() {
                            Category::Parameters
                        } else {
                            cat
                        },
                        subject: format!("param {}", p.name),
                        aspect: "default".into(),
                        was: Some(p.default.to_toml()),
                        now: Some(q.default.to_toml()),
                        old_at: at.clone(),
                        new_at: new_at.clone(),
                        witness: None,
                        breaking: !used.is_empty(),
                    };
                    c.witness = Some(if used.is_empty() {
                        "not used by the env's behaviour".into()
                    } else {
                        format!(
                            "used by {}",
                            used.iter()
                                .map(|(_, s)| s.as_str())
                                .collect::<Vec<_>>()
                                .join(", ")
                        )
                    });
                    cx.changes.push(c);
                }
                if p.fixed != q.fixed {
                    let f = |fixed: bool| if fixed { "no (fixed)" } else { "yes" }.to_string();
                    // Becoming an argument adds an option; ceasing to be one breaks callers that pass it.
                    cx.push(
                        Category::Parameters,
                        format!("param {}", p.name),
                        "constructor argument",
                        Some(f(p.fixed)),
                        Some(f(q.fixed)),
                        at.clone(),
                        new_at.clone(),
                        q.fixed,
                    );
                }
                if p.doc != q.doc {
                    cx.push(
                        Category::Documentation,
                        format!("param {}", p.name),
                        "doc",
                        Some(p.doc.clone()),
                        Some(q.doc.clone()),
                        at,
                        new_at,
                        false,
                    );
                }
            }
        }
    }
    for q in &n.params {
        if o.param(&q.name).is_none() {
            let used = uses(n, &q.name);
            let mut c = Change {
                category: Category::Parameters,
                subject: format!("param {}", q.name),
                aspect: "added".into(),
                was: None,
                now: Some(q.default.to_toml()),
                old_at: None,
                new_at: Some(pos(n, &q.name_loc)),
                witness: None,
                breaking: false,
            };
            if !used.is_empty() {
                c.witness = Some(format!(
                    "used by {}",
                    used.iter()
                        .map(|(_, s)| s.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ));
            }
            cx.changes.push(c);
        }
    }
}

/// Entries of a section as (key, TOML text, position), docs separate.
fn entries(spec: &Spec, s: &Section) -> Vec<(String, String, Pos)> {
    s.entries
        .iter()
        .map(|e| (e.key.clone(), e.value.to_toml(), pos(spec, &e.key_loc)))
        .collect()
}

fn content(spec: &Spec, s: &Section) -> Vec<(String, String)> {
    entries(spec, s)
        .into_iter()
        .filter(|(k, _, _)| k != "doc")
        .map(|(k, v, _)| (k, v))
        .collect()
}

/// Match sections by name (renames: same content, different name) and report key changes.
/// `resolved` gives a canonical resolved form, so textual changes with the same effect are
/// reported as compatible.
fn sections(
    cx: &mut Ctx,
    cat: Category,
    kind: &str,
    old: &[Section],
    new: &[Section],
    resolved: &dyn Fn(&ResolvedSpec, &str) -> Option<String>,
) {
    let (o, n) = (cx.old, cx.new);
    let mut matched_new = vec![false; new.len()];
    let mut unmatched_old = vec![];
    for s in old {
        match new.iter().position(|t| t.name == s.name) {
            Some(j) => {
                matched_new[j] = true;
                let t = &new[j];
                let same_effect = resolved(cx.old_r, &s.name) == resolved(cx.new_r, &t.name);
                let (a, b) = (entries(o, s), entries(n, t));
                for (k, v, p) in &a {
                    if cat == Category::Reward && k == "info" {
                        continue; // info keys are compared by key in `info_items`
                    }
                    let other = b.iter().find(|(k2, _, _)| k2 == k);
                    let (now, np) = match other {
                        Some((_, v2, p2)) if v2 == v => continue,
                        Some((_, v2, p2)) => (Some(v2.clone()), Some(p2.clone())),
                        None => (None, Some(pos(n, &t.name_loc))),
                    };
                    let c = key_category(cat, k);
                    cx.push(
                        c,
                        format!("{kind}.{}", s.name),
                        k.clone(),
                        Some(v.clone()),
                        now,
                        Some(p.clone()),
                        np,
                        affects(c, k, same_effect),
                    );
                }
                for (k, v, p) in &b {
                    if !(a.iter().any(|(k2, _, _)| k2 == k)
                        || (cat == Category::Reward && k == "info"))
                    {
                        let c = key_category(cat, k);
                        cx.push(
                            c,
                            format!("{kind}.{}", s.name),
                            k.clone(),
                            None,
                            Some(v.clone()),
                            Some(pos(o, &s.name_loc)),
                            Some(p.clone()),
                            affects(c, k, same_effect),
                        );
                    }
                }
                if !same_effect
                    && a.iter().zip(&b).all(|(x, y)| x.0 == y.0 && x.1 == y.1)
                    && a.len() == b.len()
                {
                    // Same text, different effect: a parameter default or the model changed under it.
                    let (was, now) = (resolved(cx.old_r, &s.name), resolved(cx.new_r, &t.name));
                    let mut ch = Change {
                        category: cat,
                        subject: format!("{kind}.{}", s.name),
                        aspect: "resolved value".into(),
                        was: None,
                        now: None,
                        old_at: Some(pos(o, &s.name_loc)),
                        new_at: Some(pos(n, &t.name_loc)),
                        witness: None,
                        breaking: true,
                    };
                    ch.witness = Some(match (was, now) {
                        (None, Some(_)) => "switched on under the default parameters".into(),
                        (Some(_), None) => "switched off under the default parameters".into(),
                        _ => "same text, different value under the default parameters".into(),
                    });
                    cx.changes.push(ch);
                }
            }
            None => unmatched_old.push(s),
        }
    }
    let added: Vec<&Section> = new
        .iter()
        .zip(&matched_new)
        .filter(|(_, m)| !**m)
        .map(|(s, _)| s)
        .collect();
    let mut renamed_to = vec![false; added.len()];
    for s in unmatched_old {
        let rename = added
            .iter()
            .enumerate()
            .find(|(j, t)| !renamed_to[*j] && content(o, s) == content(n, t));
        match rename {
            Some((j, t)) => {
                renamed_to[j] = true;
                let same = resolved(cx.old_r, &s.name).map(|x| x.replace(&s.name, ""))
                    == resolved(cx.new_r, &t.name).map(|x| x.replace(&t.name, ""));
                cx.push(
                    cat,
                    format!("{kind}.{}", s.name),
                    "renamed",
                    Some(s.name.clone()),
                    Some(t.name.clone()),
                    Some(pos(o, &s.name_loc)),
                    Some(pos(n, &t.name_loc)),
                    !same || cat == Category::Info,
                );
            }
            None => {
                let active = resolved(cx.old_r, &s.name).is_some();
                cx.push(
                    cat,
                    format!("{kind}.{}", s.name),
                    "removed",
                    Some(summary(o, s)),
                    None,
                    Some(pos(o, &s.name_loc)),
                    None,
                    active || cat == Category::Info,
                );
            }
        }
    }
    for (j, t) in added.iter().enumerate() {
        if !renamed_to[j] {
            let active = resolved(cx.new_r, &t.name).is_some();
            cx.push(
                cat,
                format!("{kind}.{}", t.name),
                "added",
                None,
                Some(summary(n, t)),
                None,
                Some(pos(n, &t.name_loc)),
                active,
            );
        }
    }
}

/// The category of one key of a section: docs are documentation, a reward term's `info` key is info.
fn key_category(section: Category, key: &str) -> Category {
    match key {
        "doc" => Category::Documentation,
        "info" if section == Category::Reward => Category::Info,
        _ => section,
    }
}

/// Whether a key change alters behaviour: info keys always do (loggers see them), docs never,
/// everything else when the resolved entity differs.
fn affects(category: Category, key: &str, same_effect: bool) -> bool {
    match category {
        Category::Documentation => false,
        Category::Info if key == "info" => true,
        _ => !same_effect,
    }
}

fn summary(spec: &Spec, s: &Section) -> String {
    let c = content(spec, s);
    format!(
        "{{ {} }}",
        c.iter()
            .map(|(k, v)| format!("{k} = {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    )
}

fn range_text(a: usize, b: usize) -> String {
    format!("[{a}:{b}]")
}

fn names_text(names: &[String]) -> String {
    match names.len() {
        0 => "nothing".into(),
        1 => names[0].clone(),
        2 => format!("{}, {}", names[0], names[1]),
        n => format!("{} … {} ({n} elements)", names[0], names[n - 1]),
    }
}

fn observation(cx: &mut Ctx) {
    let (o, n) = (cx.old_r, cx.new_r);
    let (a, b) = (o.obs_names(), n.obs_names());
    let values_same = o.observation.len() == n.observation.len()
        && o.observation
            .iter()
            .zip(&n.observation)
            .all(|(x, y)| x.name == y.name && canon(x) == canon(y));
    if a != b || !values_same {
        // Witnesses, segment by segment (matched by name).
        let mut w = vec![];
        if a.len() != b.len() {
            w.push(format!("obs dim {} → {}", a.len(), b.len()));
        }
        for s in &n.observation {
            match o.observation.iter().find(|t| t.name == s.name) {
                None => w.push(format!(
                    "{}{} added at index {} ({})",
                    s.name,
                    range_text(0, s.len()),
                    s.offset,
                    names_text(&s.element_names())
                )),
                Some(t) => {
                    let (x, y) = (t.element_names(), s.element_names());
                    if x != y {
                        let gone: Vec<String> =
                            x.iter().filter(|e| !y.contains(e)).cloned().collect();
                        let new: Vec<String> =
                            y.iter().filter(|e| !x.contains(e)).cloned().collect();
                        let mut d = format!(
                            "{} {} → {}",
                            s.name,
                            range_text(t.offset, t.offset + t.len()),
                            range_text(s.offset, s.offset + s.len())
                        );
                        if !gone.is_empty() {
                            let _ = write!(d, "; removed {}", names_text(&gone));
                        }
                        if !new.is_empty() {
                            let _ = write!(d, "; added {}", names_text(&new));
                        }
                        w.push(d);
                    } else if canon(t) != canon(s) {
                        w.push(format!(
                            "{} {}: values change (clip, function or subtraction)",
                            s.name,
                            range_text(s.offset, s.offset + s.len())
                        ));
                    } else if t.offset != s.offset {
                        w.push(format!(
                            "{} moved from index {} to {}",
                            s.name, t.offset, s.offset
                        ));
                    }
                }
            }
        }
        for t in &o.observation {
            if !n.observation.iter().any(|s| s.name == t.name) {
                w.push(format!(
                    "{}{} removed from index {} ({})",
                    t.name,
                    range_text(0, t.len()),
                    t.offset,
                    names_text(&t.element_names())
                ));
            }
        }
        let first = a
            .iter()
            .zip(&b)
            .position(|(x, y)| x != y)
            .unwrap_or(a.len().min(b.len()));
        let mut c = Change {
            category: Category::Observation,
            subject: "observation".into(),
            aspect: "layout".into(),
            was: Some(format!("{} elements", a.len())),
            now: Some(format!("{} elements", b.len())),
            old_at: None,
            new_at: None,
            witness: None,
            breaking: true,
        };
        if a != b {
            w.push(format!("first difference at index {first}"));
        }
        c.witness = Some(w.join("; "));
        cx.changes.push(c);
    }
    let (os, ns) = (&cx.old.observation, &cx.new.observation);
    sections(
        cx,
        Category::Observation,
        "observation",
        os,
        ns,
        &|r: &ResolvedSpec, name: &str| {
            r.observation.iter().find(|s| s.name == name).map(|s| {
                canon(&Segment {
                    offset: 0,
                    ..s.clone()
                })
            })
        },
    );
    // Section-level changes are breaking only if the resolved layout changed.
    let layout_changed = a != b || !values_same;
    for ch in cx
        .changes
        .iter_mut()
        .filter(|c| c.category == Category::Observation && c.subject != "observation")
    {
        if !layout_changed {
            ch.breaking = false;
        }
    }
}

fn reward_sum(cx: &mut Ctx) {
    let (o, n) = (cx.old_r, cx.new_r);
    let (a, b) = (describe::reward_sum(o), describe::reward_sum(n));
    if a != b {
        let at = |s: &Spec| s.reward_sum.as_ref().map(|v| pos(s, &v.loc));
        let (oa, na) = (at(cx.old), at(cx.new));
        cx.push(
            Category::Reward,
            "reward",
            "sum",
            Some(a),
            Some(b),
            oa,
            na,
            true,
        );
    }
}

fn episode(cx: &mut Ctx) {
    let (o, n) = (cx.old_r, cx.new_r);
    if o.terminate_when_unhealthy != n.terminate_when_unhealthy {
        cx.push(
            Category::Termination,
            "health",
            "an unhealthy state ends the episode",
            Some(o.terminate_when_unhealthy.to_string()),
            Some(n.terminate_when_unhealthy.to_string()),
            None,
            None,
            true,
        );
    }
    if o.frame_skip != n.frame_skip || o.model.timestep != n.model.timestep {
        cx.push(
            Category::Dynamics,
            "env",
            "dt = timestep × frame_skip",
            Some(format!(
                "{} × {} = {}",
                o.model.timestep,
                o.frame_skip,
                o.dt()
            )),
            Some(format!(
                "{} × {} = {}",
                n.model.timestep,
                n.frame_skip,
                n.dt()
            )),
            None,
            None,
            true,
        );
    }
}

fn reset_order(cx: &mut Ctx) {
    let names = |r: &ResolvedSpec| r.reset.iter().map(|s| s.name.clone()).collect::<Vec<_>>();
    let (a, b) = (names(cx.old_r), names(cx.new_r));
    let common_a: Vec<&String> = a.iter().filter(|x| b.contains(x)).collect();
    let common_b: Vec<&String> = b.iter().filter(|x| a.contains(x)).collect();
    if common_a != common_b {
        cx.push(
            Category::Reset,
            "reset",
            "draw order",
            Some(a.join(", ")),
            Some(b.join(", ")),
            None,
            None,
            true,
        );
    }
}

/// Where an info key is defined: an `[info.*]` table (by name or `key`), or a reward term's `info`.
fn info_pos(spec: &Spec, key: &str) -> Option<Pos> {
    for s in &spec.info {
        if s.name == key || s.str("key") == Some(key) {
            return Some(pos(spec, &s.name_loc));
        }
    }
    spec.reward
        .iter()
        .find(|t| t.str("info") == Some(key))
        .and_then(|t| t.get("info"))
        .map(|v| pos(spec, &v.loc))
}

/// Info compared by key on the resolved specs (a key may move between an `[info]` table and a
/// reward term without changing), plus documentation changes of `[info.*]` tables.
fn info_items(cx: &mut Ctx) {
    let (o, n) = (cx.old_r, cx.new_r);
    let removed: Vec<&InfoItem> = o
        .info
        .iter()
        .filter(|i| !n.info.iter().any(|j| j.key == i.key))
        .collect();
    let added: Vec<&InfoItem> = n
        .info
        .iter()
        .filter(|j| !o.info.iter().any(|i| i.key == j.key))
        .collect();
    // A key that disappears while another with the same definition appears was renamed.
    let mut renamed_to: Vec<Option<usize>> = vec![None; removed.len()];
    let mut taken = vec![false; added.len()];
    for (r, i) in removed.iter().enumerate() {
        if let Some(a) =
            (0..added.len()).find(|&a| !taken[a] && info_canon(o, i) == info_canon(n, added[a]))
        {
            taken[a] = true;
            renamed_to[r] = Some(a);
        }
    }
    // Failing that, a key moving to another key of the same reward term is a rename too (the
    // term itself may have changed; that is reported as its definition).
    for (r, i) in removed.iter().enumerate() {
        if renamed_to[r].is_some() {
            continue;
        }
        let Some(term) = info_term(o, i) else {
            continue;
        };
        if let Some(a) =
            (0..added.len()).find(|&a| !taken[a] && info_term(n, added[a]) == Some(term))
        {
            taken[a] = true;
            renamed_to[r] = Some(a);
            if info_canon(o, i) != info_canon(n, added[a]) {
                cx.push(
                    Category::Info,
                    format!("info.{}", added[a].key),
                    "definition",
                    Some(info_text(o, i)),
                    Some(info_text(n, added[a])),
                    info_pos(cx.old, &i.key),
                    info_pos(cx.new, &added[a].key),
                    true,
                );
            }
        }
    }
    for (r, i) in removed.iter().enumerate() {
        match renamed_to[r] {
            Some(a) => cx.push(
                Category::Info,
                format!("info.{}", i.key),
                "renamed",
                Some(i.key.clone()),
                Some(added[a].key.clone()),
                info_pos(cx.old, &i.key),
                info_pos(cx.new, &added[a].key),
                true,
            ),
            None => cx.push(
                Category::Info,
                format!("info.{}", i.key),
                "removed",
                Some(info_text(o, i)),
                None,
                info_pos(cx.old, &i.key),
                None,
                true,
            ),
        }
    }
    for i in &o.info {
        let Some(j) = n.info.iter().find(|j| j.key == i.key) else {
            continue;
        };
        if info_canon(o, i) != info_canon(n, j) {
            cx.push(
                Category::Info,
                format!("info.{}", i.key),
                "definition",
                Some(info_text(o, i)),
                Some(info_text(n, j)),
                info_pos(cx.old, &i.key),
                info_pos(cx.new, &j.key),
                true,
            );
        }
        if i.at_reset != j.at_reset {
            let f = |b: bool| if b { "reset and step" } else { "step only" }.to_string();
            cx.push(
                Category::Info,
                format!("info.{}", i.key),
                "reported at",
                Some(f(i.at_reset)),
                Some(f(j.at_reset)),
                info_pos(cx.old, &i.key),
                info_pos(cx.new, &j.key),
                true,
            );
        }
    }
    for (a, j) in added.iter().enumerate() {
        if !taken[a] {
            let when = if j.at_reset { "reset and step" } else { "step" };
            cx.push(
                Category::Info,
                format!("info.{}", j.key),
                "added",
                None,
                Some(format!("{} ({when})", info_text(n, j))),
                None,
                info_pos(cx.new, &j.key),
                true,
            );
        }
    }
    // `[info.*]` tables that only apply under non-default parameters and are gone in the new spec
    // (e.g. an alternative definition of a key switched on by a flag).
    for s in &cx.old.info {
        let key = s.str("key").unwrap_or(&s.name);
        let active = o
            .info
            .iter()
            .any(|i| i.key == key && info_pos(cx.old, key) == Some(pos(cx.old, &s.name_loc)));
        if !active && !cx.new.info.iter().any(|t| t.name == s.name) {
            let mut c = Change {
                category: Category::Info,
                subject: format!("info.{}", s.name),
                aspect: "removed".into(),
                was: Some(summary(cx.old, s)),
                now: None,
                old_at: Some(pos(cx.old, &s.name_loc)),
                new_at: None,
                witness: Some("it applied only under non-default parameters".into()),
                breaking: false,
            };
            if let Some(w) = s.get("when") {
                c.witness = Some(format!("it applied only when {}", w.to_toml()));
            }
            cx.changes.push(c);
        }
    }
    for s in &cx.old.info {
        let Some(t) = cx.new.info.iter().find(|t| t.name == s.name) else {
            continue;
        };
        if s.doc() != t.doc() {
            let (a, b) = (
                Some(pos(cx.old, &s.name_loc)),
                Some(pos(cx.new, &t.name_loc)),
            );
            cx.push(
                Category::Documentation,
                format!("info.{}", s.name),
                "doc",
                Some(s.doc()),
                Some(t.doc()),
                a,
                b,
                false,
            );
        }
    }
}

/// An info entry's definition, with the weight of a reward-term entry spelled out.
fn info_text(r: &ResolvedSpec, i: &InfoItem) -> String {
    match &i.kind {
        InfoKind::Term(t) => {
            let term = &r.reward[*t];
            let w = if i.unweighted {
                " without its weight".to_string()
            } else {
                String::new()
            };
            format!("reward term `{}`{w}: {}", term.name, describe::term(term))
        }
        _ => describe::info(r, i),
    }
}

impl Report {
    /// Add changes (e.g. compiled-model differences found by the runtime), keeping the report
    /// ordered by category and its flags up to date.
    pub fn extend(&mut self, more: Vec<Change>) {
        self.changes.extend(more);
        self.changes.sort_by_key(|c| c.category);
        self.flags.clear();
        let breaks_policies = self
            .changes
            .iter()
            .any(|c| c.breaking && matches!(c.category, Category::Observation | Category::Action));
        if breaks_policies && self.old_id == self.new_id {
            self.flags.push(format!(
                "this change breaks trained policies but the env id stays `{}`: bump its version",
                self.new_id
            ));
        }
    }

    pub fn verdict(&self) -> Verdict {
        if self.changes.is_empty() {
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
            .map(|c| c.category)
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

    fn line(c: &Change) -> String {
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
        let mark = if c.breaking { "!" } else { " " };
        format!("{mark} {}: {body}", c.subject)
    }

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
            if cat != Some(c.category) {
                cat = Some(c.category);
                let _ = writeln!(o, "\n{} — {}", c.category.title(), c.category.impact());
            }
            let _ = writeln!(o, "  {}", Self::line(c));
            if let Some(w) = &c.witness {
                let _ = writeln!(o, "      {w}");
            }
        }
        if !self.changes.is_empty() {
            let _ = writeln!(o, "\n(! marks changes that alter behaviour)");
        }
        o
    }

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
            if cat != Some(c.category) {
                cat = Some(c.category);
                let _ = writeln!(
                    o,
                    "\n#### {} — {}\n",
                    c.category.title(),
                    c.category.impact()
                );
                let _ = writeln!(o, "| | what | was | now | note |\n|---|---|---|---|---|");
            }
            let cell = |v: &Option<String>, p: &Option<Pos>| {
                let v = v
                    .as_deref()
                    .map(|v| format!("`{}`", esc(v)))
                    .unwrap_or_else(|| "—".into());
                match p {
                    Some(p) => format!("{v} <sub>{p}</sub>"),
                    None => v,
                }
            };
            let _ = writeln!(
                o,
                "| {} | {} {} | {} | {} | {} |",
                if c.breaking { "⚠️" } else { "" },
                esc(&c.subject),
                esc(&c.aspect),
                cell(&c.was, &c.old_at),
                cell(&c.now, &c.new_at),
                esc(c.witness.as_deref().unwrap_or(""))
            );
        }
        o
    }

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
            } else if c.category == Category::Documentation {
                "notice"
            } else {
                "warning"
            };
            let at = c.new_at.as_ref().or(c.old_at.as_ref());
            let loc = at
                .map(|p| format!(" file={},line={}", p.file, p.line))
                .unwrap_or_else(|| format!(" file={}", self.new_file));
            let mut msg = Self::line(c).trim_start_matches(['!', ' ']).to_string();
            if let Some(w) = &c.witness {
                msg.push_str(&format!(" — {w}"));
            }
            let _ = writeln!(
                o,
                "::{level}{loc},title=envc diff: {}::{}",
                c.category.title(),
                esc(&msg)
            );
        }
        o
    }
}

#[cfg(test)]
mod tests {
    use super::canon;

    #[test]
    fn canon_drops_names_docs_and_selector_spelling() {
        #[derive(Debug)]
        #[allow(dead_code)]
        struct S {
            name: String,
            text: String,
            doc: String,
            indices: Vec<usize>,
        }
        let a = S {
            name: "a".into(),
            text: "xpos[$b]".into(),
            doc: "say \"hi\"".into(),
            indices: vec![3],
        };
        let b = S {
            name: "b".into(),
            text: "xpos[torso]".into(),
            doc: String::new(),
            indices: vec![3],
        };
        assert_eq!(canon(&a), canon(&b));
        let c = S {
            name: "a".into(),
            text: "xpos[$b]".into(),
            doc: String::new(),
            indices: vec![4],
        };
        assert_ne!(canon(&a), canon(&c));
    }
}
