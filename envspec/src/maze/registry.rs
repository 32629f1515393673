//! Registry files: `[[family]]` tables expanding one maze spec over several maps and both
//! reward types into registered ids, or one task spec over both reward types (`id` without
//! `{map}`, no `maps`: Gymnasium-Robotics' `FetchReach-v4` and `FetchReachDense-v4`).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::diagnostic::{Code, Diagnostic, Diagnostics, SourceFile, suggest};
use crate::params::Override;
use crate::value::{Val, ValKind};

/// A registered family: a maze spec run over several maps and both reward types.
#[derive(Clone, Debug)]
pub struct Registered {
    /// The env id it registers, e.g. `PointMaze_UMaze-v3`.
    pub id: String,
    /// The maze spec it runs.
    pub spec: PathBuf,
    /// Parameters set for this id (the map, the reward type).
    pub overrides: Vec<Override>,
}

const FAMILY_KEYS: &[&str] = &["spec", "id", "maps", "rewards"];
/// Gymnasium-Robotics' Fetch and maze suffixes: `""` sparse, `"Dense"` dense.
const DEFAULT_REWARDS: [(&str, &str); 2] = [("", "sparse"), ("Dense", "dense")];

/// Read a maze registry file: `[[family]] spec = "...", id = "PointMaze_{map}{reward}-v3"` with
/// `[family.maps] UMaze = { map = "maps/u_maze.toml", max_episode_steps = 300 }`. `{reward}` is
/// `""` for sparse and `"Dense"` for dense, as Gymnasium-Robotics registers them. Map paths are
/// relative to the registry file.
pub fn registry(path: &Path) -> Result<Vec<Registered>, Diagnostics> {
    let (file, root) = crate::value::read_document(path, None, "maze registry")?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut d = Diagnostics::default();
    let mut out = vec![];
    for f in families(&file, &root, &mut d) {
        family(f, dir, &mut d, &mut out);
    }
    out.sort_by(|a, b| a.id.cmp(&b.id));
    d.into_result(out)
}

/// The `[[family]]` entries of a registry file; any other top-level key is E0101.
fn families<'a>(file: &Arc<SourceFile>, root: &'a Val, d: &mut Diagnostics) -> &'a [Val] {
    let top = root.as_table().unwrap_or(&[]);
    for e in top.iter().filter(|e| e.key != "family") {
        d.push(
            Diagnostic::new(
                Code::E0101,
                format!("unknown key `{}` in a maze registry", e.key),
            )
            .at(e.key_loc.clone())
            .label("expected [[family]] tables")
            .help_opt(suggest(&e.key, ["family"])),
        );
    }
    match top.iter().find(|e| e.key == "family") {
        None => {
            d.push(
                Diagnostic::new(Code::E0103, "a maze registry needs [[family]] entries")
                    .at(crate::diagnostic::Location::new(file, 0..0))
                    .label("expected [[family]] with `spec`, `id` and `maps`"),
            );
            &[]
        }
        Some(e) => match &e.value.kind {
            ValKind::Array(a) => a,
            _ => {
                d.push(
                    e.value
                        .type_error("`family`", "an array of tables ([[family]])"),
                );
                &[]
            }
        },
    }
}

/// One `[[family]]` entry: its keys checked, then an id for each map and reward type.
fn family(f: &Val, dir: &Path, d: &mut Diagnostics, out: &mut Vec<Registered>) {
    let Some(t) = f.as_table() else {
        d.push(f.type_error("a [[family]] entry", "a table"));
        return;
    };
    for e in t.iter().filter(|e| !FAMILY_KEYS.contains(&e.key.as_str())) {
        d.push(
            Diagnostic::new(
                Code::E0101,
                format!("unknown key `{}` in [[family]]", e.key),
            )
            .at(e.key_loc.clone())
            .label(format!("expected one of: {}", FAMILY_KEYS.join(", ")))
            .help_opt(suggest(&e.key, FAMILY_KEYS.iter().copied())),
        );
    }
    let get = |k: &str| t.iter().find(|e| e.key == k).map(|e| &e.value);
    let mut need = |k: &str, ok: bool, expected: &str| -> bool {
        match get(k) {
            None => d.push(
                Diagnostic::new(Code::E0103, format!("missing `{k}` in [[family]]"))
                    .at(f.loc.clone())
                    .label(format!("expected `{k}`: {expected}")),
            ),
            Some(v) if !ok => d.push(v.type_error(&format!("`{k}`"), expected)),
            Some(_) => return true,
        }
        false
    };
    let spec = get("spec").and_then(Val::as_str);
    let id = get("id").and_then(Val::as_str);
    let maps = get("maps").and_then(Val::as_table);
    // Without `{map}` in the id, the family is one spec over both reward types.
    let mapless = id.is_some_and(|i| !i.contains("{map}")) && get("maps").is_none();
    let ok = [
        need("spec", spec.is_some(), "a string (the spec path)"),
        need("id", id.is_some(), "a string with {map} and {reward}"),
        mapless || need("maps", maps.is_some(), "a table of map entries"),
    ];
    let one = [crate::value::Entry {
        key: String::new(),
        key_loc: f.loc.clone(),
        value: Val {
            kind: ValKind::Table(vec![]),
            loc: f.loc.clone(),
        },
    }];
    let maps = if mapless { Some(&one[..]) } else { maps };
    let Some(rewards) = rewards(get("rewards"), d) else {
        return;
    };
    let (Some(spec), Some(id), Some(maps), [true, true, true]) = (spec, id, maps, ok) else {
        return;
    };
    for m in maps {
        map_ids(m, dir, spec, id, &rewards, d, out);
    }
}

/// `rewards = { "" = "dense", Sparse = "sparse" }`: each `{reward}` suffix with the
/// `reward_type` it sets (Adroit registers its dense reward without a suffix). None when the
/// table is malformed (reported).
fn rewards(v: Option<&Val>, d: &mut Diagnostics) -> Option<Vec<(String, String)>> {
    let Some(v) = v else {
        return Some(
            DEFAULT_REWARDS
                .iter()
                .map(|(a, b)| (a.to_string(), b.to_string()))
                .collect(),
        );
    };
    let pairs: Option<Vec<(String, String)>> = v.as_table().and_then(|t| {
        t.iter()
            .map(|e| Some((e.key.clone(), e.value.as_str()?.to_string())))
            .collect()
    });
    match pairs {
        Some(p) if !p.is_empty() => Some(p),
        _ => {
            d.push(v.type_error(
                "`rewards`",
                "a table of id suffix = reward_type, e.g. { \"\" = \"dense\", Sparse = \"sparse\" }",
            ));
            None
        }
    }
}

/// The ids of one map entry of a family, one per reward type, with the overrides each sets.
fn map_ids(
    m: &crate::value::Entry,
    dir: &Path,
    spec: &str,
    id: &str,
    rewards: &[(String, String)],
    d: &mut Diagnostics,
    out: &mut Vec<Registered>,
) {
    let Some(entry) = m.value.as_table() else {
        d.push(
            m.value
                .type_error("a map entry", "a table of maze parameters"),
        );
        return;
    };
    for (suffix, rt) in rewards {
        let mut overrides = vec![Override::text("reward_type", &format!("\"{rt}\""))];
        for e in entry {
            let text = match (e.key.as_str(), e.value.as_str()) {
                // Paths are relative to the registry file, as the spec path is.
                ("map" | "xml_file", Some(s)) => {
                    format!("{:?}", dir.join(s).display().to_string())
                }
                _ => e.value.to_toml(),
            };
            overrides.push(Override::text(&e.key, &text));
        }
        let id = id.replace("{map}", &m.key).replace("{reward}", suffix);
        // The map's key makes part of the id: a key Gymnasium's grammar refuses is E0111
        // where the key is written.
        if let Some(bad) = crate::syntax::env_id_problem(&id, m.key_loc.clone()) {
            d.push(bad);
            continue;
        }
        out.push(Registered {
            id,
            spec: dir.join(spec),
            overrides,
        });
    }
}
