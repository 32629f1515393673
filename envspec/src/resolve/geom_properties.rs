//! `[geom_properties]`: contact properties of the model's named geoms by glob pattern (a model
//! edit, resolved with `[actuators]`).

use crate::diagnostic::{Code, Diagnostic, Diagnostics};
use crate::ir::{GeomEdit, ModelEdits};
use crate::syntax::Section;
use crate::value::{Val, ValKind};

use super::Ctx;

/// E0161 at `v`.
fn bad(d: &mut Diagnostics, v: &Val, msg: String, label: &str) {
    d.push(
        Diagnostic::new(Code::E0161, msg)
            .at(v.loc.clone())
            .label(label.to_string()),
    );
}

impl Ctx<'_> {
    /// `[geom_properties]`: contact properties of the named geoms by glob pattern, rows in file
    /// order (later rows win), each row matching at least one geom.
    pub(super) fn geom_properties(&mut self, edits: &mut ModelEdits) {
        let rows = &self.spec.geom_properties;
        if rows.is_empty() {
            return;
        }
        let geoms: Vec<String> = self
            .model
            .geoms
            .iter()
            .filter(|g| !g.is_empty())
            .cloned()
            .collect();
        let mut table: Vec<GeomEdit> = geoms
            .iter()
            .map(|g| GeomEdit {
                geom: g.clone(),
                ..Default::default()
            })
            .collect();
        for row in rows {
            let Some(hit) = self.glob_hits(
                &row.name,
                geoms.iter().map(String::as_str),
                &row.name_loc,
                &format!(
                    "the {} named geoms of {}",
                    geoms.len(),
                    self.model.path.display()
                ),
                "a glob pattern over geom names (`*`: any run of characters, `?`: one)",
            ) else {
                continue;
            };
            let mut set: Vec<(String, Vec<f64>)> = vec![];
            self.geom_ints(row, &hit, &mut table, &mut set);
            self.geom_reals(row, &hit, &mut table, &mut set);
            self.geom_arrays(row, &hit, &mut table, &mut set);
            for &i in &hit {
                if !set.is_empty() && !table[i].rows.contains(&row.name) {
                    table[i].rows.push(row.name.clone());
                }
            }
            edits.geom_rows.push((
                row.name.clone(),
                hit.iter().map(|&i| geoms[i].clone()).collect(),
                set,
            ));
        }
        edits.geoms = table.into_iter().filter(|e| !e.rows.is_empty()).collect();
    }

    /// A row's integer keys (`contype`, `conaffinity`, `condim`, `priority`): whole numbers
    /// ≥ 0, and condim 1, 3, 4 or 6.
    fn geom_ints(
        &mut self,
        row: &Section,
        hit: &[usize],
        table: &mut [GeomEdit],
        set: &mut Vec<(String, Vec<f64>)>,
    ) {
        let what = |k: &str| format!("geom_properties.\"{}\".{k}", row.name);
        for (k, key) in GeomEdit::INTS.iter().enumerate() {
            let Some(v) = row.get(key) else { continue };
            let Some(x) = self.num(v, &what(key)) else {
                continue;
            };
            let ok = x.fract() == 0.0
                && x >= 0.0
                && x <= f64::from(i32::MAX)
                && (*key != "condim" || [1.0, 3.0, 4.0, 6.0].contains(&x));
            if !ok {
                let label = if *key == "condim" {
                    "expected 1, 3, 4 or 6"
                } else {
                    "expected a whole number ≥ 0"
                };
                bad(&mut self.d, v, format!("{} is {x}", what(key)), label);
                continue;
            }
            set.push((key.to_string(), vec![x]));
            for &i in hit {
                table[i].ints[k] = Some(x as i32);
            }
        }
    }

    /// A row's real keys (`solmix`, `margin`, `gap`): finite, and solmix ≥ 0.
    fn geom_reals(
        &mut self,
        row: &Section,
        hit: &[usize],
        table: &mut [GeomEdit],
        set: &mut Vec<(String, Vec<f64>)>,
    ) {
        let what = |k: &str| format!("geom_properties.\"{}\".{k}", row.name);
        for (k, key) in GeomEdit::REALS.iter().enumerate() {
            let Some(v) = row.get(key) else { continue };
            let Some(x) = self.num_within(v, &what(key), crate::limits::MAX_MAGNITUDE) else {
                continue;
            };
            if !x.is_finite() || (*key == "solmix" && x < 0.0) {
                bad(
                    &mut self.d,
                    v,
                    format!("{} is {x}", what(key)),
                    "expected a finite number",
                );
                continue;
            }
            set.push((key.to_string(), vec![x]));
            for &i in hit {
                table[i].reals[k] = Some(x);
            }
        }
    }

    /// A row's array keys (`friction`, `solref`, `solimp`): up to their length, the leading
    /// entries set.
    fn geom_arrays(
        &mut self,
        row: &Section,
        hit: &[usize],
        table: &mut [GeomEdit],
        set: &mut Vec<(String, Vec<f64>)>,
    ) {
        let what = |k: &str| format!("geom_properties.\"{}\".{k}", row.name);
        for (key, most) in GeomEdit::ARRAYS {
            let Some(v) = row.get(key) else { continue };
            let values = match &v.kind {
                ValKind::Array(a) if !a.is_empty() && a.len() <= most => a
                    .iter()
                    .map(|x| self.num_within(x, &what(key), crate::limits::MAX_MAGNITUDE))
                    .collect::<Option<Vec<f64>>>(),
                ValKind::Array(a) => {
                    bad(
                        &mut self.d,
                        v,
                        format!("{} has {} numbers", what(key), a.len()),
                        &format!("expected 1 to {most} numbers (the leading entries are set)"),
                    );
                    None
                }
                _ => {
                    self.d.push(v.type_error(&what(key), "an array of numbers"));
                    None
                }
            };
            let Some(values) = values else { continue };
            if values.iter().any(|x| !x.is_finite()) {
                bad(
                    &mut self.d,
                    v,
                    format!("{} is not finite", what(key)),
                    "expected finite numbers",
                );
                continue;
            }
            set.push((key.to_string(), values.clone()));
            for &i in hit {
                let e = &mut table[i];
                match key {
                    "friction" => e.friction.clone_from(&values),
                    "solref" => e.solref.clone_from(&values),
                    _ => e.solimp.clone_from(&values),
                }
            }
        }
    }
}
