//! The observation: the resolved vector compared element by element (witnesses: dimensions,
//! indices, element names), then the `[observation.*]` sections, whose changes alter behaviour
//! only when the resolved layout changed.

use std::fmt::Write;

use super::rules::{Category, RuleId};
use super::{Change, Ctx, behaviour, sections};
use crate::ir::ResolvedSpec;

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

/// What differs, segment by segment (matched by name).
fn witness(o: &ResolvedSpec, n: &ResolvedSpec, a: &[String], b: &[String]) -> String {
    let mut w = vec![];
    if a.len() != b.len() {
        w.push(format!("obs dim {} → {}", a.len(), b.len()));
    }
    for s in &n.observation {
        let Some(t) = o.observation.iter().find(|t| t.name == s.name) else {
            w.push(format!(
                "{}{} added at index {} ({})",
                s.name,
                range_text(0, s.len()),
                s.offset,
                names_text(&s.element_names())
            ));
            continue;
        };
        let (x, y) = (t.element_names(), s.element_names());
        if x != y {
            let gone: Vec<String> = x.iter().filter(|e| !y.contains(e)).cloned().collect();
            let new: Vec<String> = y.iter().filter(|e| !x.contains(e)).cloned().collect();
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
        } else if behaviour::segment(t) != behaviour::segment(s) {
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
    if a != b {
        let first = a
            .iter()
            .zip(b)
            .position(|(x, y)| x != y)
            .unwrap_or(a.len().min(b.len()));
        w.push(format!("first difference at index {first}"));
    }
    w.join("; ")
}

pub(super) fn observation(cx: &mut Ctx) {
    let (o, n) = (cx.old_r, cx.new_r);
    let (a, b) = (o.obs_names(), n.obs_names());
    let values_same = o.observation.len() == n.observation.len()
        && o.observation
            .iter()
            .zip(&n.observation)
            .all(|(x, y)| x.name == y.name && behaviour::segment(x) == behaviour::segment(y));
    let layout_changed = a != b || !values_same;
    if layout_changed {
        cx.add(
            Change::new(RuleId::ObservationLayoutChanged, "observation", "layout")
                .values(
                    Some(format!("{} elements", a.len())),
                    Some(format!("{} elements", b.len())),
                )
                .witness(witness(o, n, &a, &b)),
        );
    }
    let (os, ns) = (&cx.old.observation, &cx.new.observation);
    sections::sections(
        cx,
        &sections::OBSERVATION,
        os,
        ns,
        &|r: &ResolvedSpec, name: &str| {
            r.observation
                .iter()
                .find(|s| s.name == name)
                .map(behaviour::segment)
        },
    );
    // Section-level changes (and parameter defaults read by the observation) alter behaviour
    // only if the resolved layout changed.
    if !layout_changed {
        for ch in cx
            .changes
            .iter_mut()
            .filter(|c| c.category() == Category::Observation && c.subject != "observation")
        {
            ch.breaking = false;
        }
    }
}
