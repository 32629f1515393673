//! `[terrain]`: a grid of generated tiles (mjlab's terrain generator as data), and the reset kind
//! that spawns on a tile (`terrain_origin`). Only the generators' parameters are resolved here;
//! the runtime builds the geoms (`envc::terrain`), since the random layout draws from numpy's
//! generator, which lives there.

use crate::diagnostic::{Code, Diagnostic};
use crate::ir::{Distribution, ResetStep, Terrain, TerrainTile, TileKind};
use crate::limits::{MAX_GEOMS, MAX_TERRAIN_CELLS, MAX_TERRAIN_LEVELS, MAX_TERRAIN_TILES};
use crate::syntax::{Section, terrain_tiles};
use crate::value::Val;

use super::Ctx;

/// The largest tile side and border, in metres (a 1 km tile is already far beyond any task).
const MAX_TILE_SIZE: f64 = 1000.0;

impl Ctx<'_> {
    fn e0105(&mut self, v: &Val, message: String, label: &str) {
        self.d.push(
            Diagnostic::new(Code::E0105, message)
                .at(v.loc.clone())
                .label(label.to_string()),
        );
    }

    /// A number in `[lo, hi]` (`open`: above `lo`), or the default when the key is absent.
    fn bounded(&mut self, s: &Section, key: &str, default: f64, lo: f64, hi: f64) -> Option<f64> {
        let Some(v) = s.get(key) else {
            return Some(default);
        };
        let what = format!("{}.{key}", section_name(s));
        let x = self.num(v, &what)?;
        if !(lo..=hi).contains(&x) {
            self.e0105(
                v,
                format!("{what} = {x} is outside [{lo}, {hi}]"),
                &format!("expected a number in [{lo}, {hi}]"),
            );
            return None;
        }
        Some(x)
    }

    /// A positive number at most `hi` (or the default).
    fn positive(&mut self, s: &Section, key: &str, default: f64, hi: f64) -> Option<f64> {
        let x = self.bounded(s, key, default, 0.0, hi)?;
        if x <= 0.0 {
            let v = s.get(key)?;
            self.e0105(
                v,
                format!("{}.{key} must be above 0", section_name(s)),
                "expected a positive number",
            );
            return None;
        }
        Some(x)
    }

    /// A whole number in `[lo, hi]` (or the default).
    fn count(
        &mut self,
        s: &Section,
        key: &str,
        default: usize,
        lo: usize,
        hi: usize,
    ) -> Option<usize> {
        let x = self.bounded(s, key, default as f64, lo as f64, hi as f64)?;
        if x.fract() != 0.0 {
            let v = s.get(key)?;
            self.e0105(
                v,
                format!("{}.{key} = {x} is not a whole number", section_name(s)),
                "expected an integer",
            );
            return None;
        }
        Some(x as usize)
    }

    /// A range within `[lo, hi]` (or the default).
    fn span(
        &mut self,
        s: &Section,
        key: &str,
        default: (f64, f64),
        lo: f64,
        hi: f64,
    ) -> Option<(f64, f64)> {
        let Some(v) = s.get(key) else {
            return Some(default);
        };
        let what = format!("{}.{key}", section_name(s));
        let r = self.range(v, &what)?;
        if !(r.0 >= lo && r.1 <= hi && r.0 <= r.1) {
            self.e0105(
                v,
                format!("{what} = [{}, {}] is not within [{lo}, {hi}]", r.0, r.1),
                &format!("expected [low, high] with {lo} ≤ low ≤ high ≤ {hi}"),
            );
            return None;
        }
        Some(r)
    }

    fn switch(&mut self, s: &Section, key: &str) -> Option<bool> {
        match s.get(key) {
            None => Some(false),
            Some(v) => self.flag(v, &format!("{}.{key}", section_name(s))),
        }
    }

    /// `[terrain]`, resolved (None when the spec has none or it has errors, reported).
    pub(super) fn terrain(&mut self) -> Option<Terrain> {
        let s = self.spec.terrain.as_ref()?;
        let errors = self.d.0.len();
        let tile_size = self.tile_size(s);
        let layout = self.terrain_layout(s);
        let tiles = self.terrain_generators(s);
        let rows = self.count(s, "rows", 10, 1, MAX_TERRAIN_TILES);
        let cols = match (layout, &tiles) {
            // One column per generator in the curriculum layout, as mjlab's.
            (Some(true), Some(t)) => {
                if let Some(v) = s.get("cols")
                    && self.count(s, "cols", 0, 1, MAX_TERRAIN_TILES) != Some(t.len())
                {
                    self.e0105(
                        v,
                        format!(
                            "the curriculum layout has one column per generator ({}); `cols` says otherwise",
                            t.len()
                        ),
                        "leave `cols` out, or use layout = \"random\"",
                    );
                }
                Some(t.len())
            }
            _ => self.count(s, "cols", 20, 1, MAX_TERRAIN_TILES),
        };
        let border_width = self.bounded(s, "border_width", 0.0, 0.0, MAX_TILE_SIZE);
        let border_height = self.positive(s, "border_height", 1.0, MAX_TILE_SIZE);
        let seed = self.count(s, "seed", 0, 0, u32::MAX as usize);
        let difficulty = self.span(s, "difficulty", (0.0, 1.0), 0.0, 1.0);
        let (Some(tile_size), Some(curriculum), Some(tiles), Some(rows), Some(cols)) =
            (tile_size, layout, tiles, rows, cols)
        else {
            return None;
        };
        self.terrain_size(s, tile_size, &tiles, rows, cols)?;
        self.terrain_work(s, tile_size, &tiles, curriculum, rows, cols, border_width);
        if self.d.0.len() > errors {
            return None;
        }
        Some(Terrain {
            tile_size,
            rows,
            cols,
            border_width: border_width?,
            border_height: border_height?,
            seed: seed? as u64,
            curriculum,
            difficulty: difficulty?,
            tiles,
        })
    }

    /// `tile_size`: one side, or `[x, y]`, in (0, 1000] metres (8 by default).
    fn tile_size(&mut self, s: &Section) -> Option<[f64; 2]> {
        match s.get("tile_size") {
            None => Some([8.0, 8.0]),
            Some(v) => match &v.kind {
                crate::value::ValKind::Array(a) if a.len() == 2 => {
                    let x = self.num(&a[0], "terrain.tile_size");
                    let y = self.num(&a[1], "terrain.tile_size");
                    match (x, y) {
                        (Some(x), Some(y)) if x > 0.0 && y > 0.0 && x.max(y) <= MAX_TILE_SIZE => {
                            Some([x, y])
                        }
                        (Some(_), Some(_)) => {
                            self.e0105(
                                v,
                                "terrain.tile_size must be two sides in (0, 1000] metres".into(),
                                "expected [x, y] in metres",
                            );
                            None
                        }
                        _ => None,
                    }
                }
                _ => self
                    .positive(s, "tile_size", 8.0, MAX_TILE_SIZE)
                    .map(|x| [x, x]),
            },
        }
    }

    /// `layout`: "curriculum" (true, the default) or "random" (false).
    fn terrain_layout(&mut self, s: &Section) -> Option<bool> {
        match s.get("layout") {
            None => Some(true),
            Some(v) => match v.as_str() {
                Some("curriculum") => Some(true),
                Some("random") => Some(false),
                _ => {
                    self.d.push(
                        Diagnostic::new(
                            Code::E0104,
                            format!("unknown terrain layout {}", v.to_toml()),
                        )
                        .at(v.loc.clone())
                        .label("expected \"curriculum\" or \"random\""),
                    );
                    None
                }
            },
        }
    }

    /// E0110 when the grid has too many tiles, or could make too many heightfield cells.
    fn terrain_size(
        &mut self,
        s: &Section,
        tile_size: [f64; 2],
        tiles: &[TerrainTile],
        rows: usize,
        cols: usize,
    ) -> Option<()> {
        if rows * cols > MAX_TERRAIN_TILES {
            self.d.push(
                Diagnostic::new(
                    Code::E0110,
                    format!(
                        "[terrain] has {rows} × {cols} = {} tiles, beyond envc's limit of {MAX_TERRAIN_TILES}",
                        rows * cols
                    ),
                )
                .at(s.name_loc.clone())
                .label(format!("expected at most {MAX_TERRAIN_TILES} tiles")),
            );
            return None;
        }
        // Heightfield cells in the worst case (every tile a heightfield).
        let cells = tiles
            .iter()
            .filter_map(|t| match t.kind {
                TileKind::PyramidSlope {
                    horizontal_scale, ..
                }
                | TileKind::RandomUniform {
                    horizontal_scale, ..
                } => Some(
                    ((tile_size[0] / horizontal_scale) * (tile_size[1] / horizontal_scale))
                        as usize,
                ),
                _ => None,
            })
            .max()
            .unwrap_or(0)
            .saturating_mul(rows * cols);
        if cells > MAX_TERRAIN_CELLS {
            self.d.push(
                Diagnostic::new(
                    Code::E0110,
                    format!(
                        "[terrain] could make {cells} heightfield cells, beyond envc's limit of {MAX_TERRAIN_CELLS}"
                    ),
                )
                .at(s.name_loc.clone())
                .label("fewer or smaller tiles, or a coarser horizontal_scale"),
            );
            return None;
        }
        Some(())
    }

    /// Bounds on what the terrain makes, checked before the runtime allocates anything: each
    /// heightfield's integer height levels, and the geoms of the whole model.
    #[allow(clippy::too_many_arguments)]
    fn terrain_work(
        &mut self,
        s: &Section,
        tile_size: [f64; 2],
        tiles: &[TerrainTile],
        curriculum: bool,
        rows: usize,
        cols: usize,
        border_width: Option<f64>,
    ) {
        let sections = terrain_tiles(&s.entries);
        let mut geoms = vec![];
        for (t, sec) in tiles.iter().zip(&sections) {
            geoms.push(tile_geoms(&t.kind, tile_size));
            if let Some((levels, key)) = tile_levels(&t.kind, tile_size)
                && (levels > MAX_TERRAIN_LEVELS || !levels.is_finite())
            {
                let at = key.iter().find_map(|k| sec.get(k));
                self.d.push(
                        Diagnostic::new(
                            Code::E0110,
                            format!(
                                "terrain.{} would need {levels:.3e} height levels, beyond envc's limit of {MAX_TERRAIN_LEVELS:e}",
                                sec.name
                            ),
                        )
                        .at(at.map_or(sec.name_loc.clone(), |v| v.loc.clone()))
                        .label(format!("heights are whole multiples of vertical_scale; expected at most {MAX_TERRAIN_LEVELS:e} of them"))
                        .help("a larger vertical_scale (or noise_step), or smaller heights; see docs/limits.md"),
                    );
            }
        }
        let n = (rows * cols) as f64;
        let terrain = if curriculum {
            rows as f64 * geoms.iter().sum::<f64>()
        } else {
            n * tiles
                .iter()
                .zip(&geoms)
                .filter(|(t, _)| t.proportion > 0.0)
                .map(|(_, g)| *g)
                .fold(0.0, f64::max)
        } + if border_width.is_some_and(|b| b > 0.0) {
            4.0
        } else {
            0.0
        };
        let total = terrain + self.model.geoms.len() as f64;
        if total > MAX_GEOMS as f64 {
            // Located at the generator that makes the most.
            let (i, _) = geoms
                .iter()
                .enumerate()
                .fold((0, 0.0), |b, (i, &g)| if g > b.1 { (i, g) } else { b });
            let sec = &sections[i.min(sections.len().saturating_sub(1))];
            let at = sec
                .get("step_width")
                .map_or(sec.name_loc.clone(), |v| v.loc.clone());
            self.d.push(
                Diagnostic::new(
                    Code::E0110,
                    format!(
                        "[terrain] would make {terrain:.0} geoms ({:.0} per terrain.{} tile), {total:.0} in the model, beyond envc's limit of {MAX_GEOMS}",
                        geoms.get(i).copied().unwrap_or(0.0),
                        sec.name
                    ),
                )
                .at(at)
                .label(format!("expected at most {MAX_GEOMS} geoms in all"))
                .help("MuJoCo's compile time grows with the square of the geom count: wider steps, smaller or fewer tiles; see docs/limits.md"),
            );
        }
    }

    /// The `[terrain.<name>]` generators (at least one).
    fn terrain_generators(&mut self, s: &Section) -> Option<Vec<TerrainTile>> {
        let sections = terrain_tiles(&s.entries);
        if sections.is_empty() {
            self.d.push(
                Diagnostic::new(Code::E0103, "[terrain] has no tile generator")
                    .at(s.name_loc.clone())
                    .label("expected at least one [terrain.<name>] table with a `kind`"),
            );
            return None;
        }
        let mut out = vec![];
        for t in &sections {
            let proportion = self.bounded(t, "proportion", 1.0, 0.0, 1e6);
            let kind = match t.kind("") {
                "flat" => Some(TileKind::Flat),
                "pyramid_stairs" => self.stairs(t),
                "pyramid_slope" => self.slope(t),
                "random_uniform" => self.random_uniform(t),
                // An unknown or missing kind was reported with the keys.
                _ => None,
            };
            if let (Some(proportion), Some(kind)) = (proportion, kind) {
                out.push(TerrainTile {
                    name: t.name.clone(),
                    proportion,
                    kind,
                });
            }
        }
        if out.len() == sections.len() && out.iter().all(|t| t.proportion == 0.0) {
            self.d.push(
                Diagnostic::new(Code::E0105, "every [terrain] generator has proportion 0")
                    .at(s.name_loc.clone())
                    .label("expected a positive proportion somewhere"),
            );
            return None;
        }
        (out.len() == sections.len()).then_some(out)
    }

    fn stairs(&mut self, t: &Section) -> Option<TileKind> {
        let step_height = self.span(t, "step_height", (0.0, 0.1), 0.0, MAX_TILE_SIZE);
        let step_width = self.positive(t, "step_width", 0.3, MAX_TILE_SIZE);
        let platform_width = self.bounded(t, "platform_width", 1.0, 0.0, MAX_TILE_SIZE);
        let border_width = self.bounded(t, "border_width", 0.0, 0.0, MAX_TILE_SIZE);
        let inverted = self.switch(t, "inverted");
        Some(TileKind::PyramidStairs {
            step_height: step_height?,
            step_width: step_width?,
            platform_width: platform_width?,
            border_width: border_width?,
            inverted: inverted?,
        })
    }

    /// The heightfield scales, and a border at least one cell wide (mjlab refuses a thinner one).
    fn scales(&mut self, t: &Section) -> Option<(f64, f64, f64)> {
        let horizontal = self.positive(t, "horizontal_scale", 0.1, MAX_TILE_SIZE)?;
        let vertical = self.positive(t, "vertical_scale", 0.005, MAX_TILE_SIZE)?;
        let border = self.bounded(t, "border_width", 0.0, 0.0, MAX_TILE_SIZE)?;
        if border > 0.0 && border < horizontal {
            let v = t.get("border_width")?;
            self.e0105(
                v,
                format!(
                    "terrain.{}.border_width = {border} is narrower than one cell ({horizontal} m)",
                    t.name
                ),
                "expected 0, or at least horizontal_scale",
            );
            return None;
        }
        Some((horizontal, vertical, border))
    }

    fn slope(&mut self, t: &Section) -> Option<TileKind> {
        let slope = self.span(t, "slope", (0.0, 1.0), 0.0, MAX_TILE_SIZE);
        let platform_width = self.bounded(t, "platform_width", 1.0, 0.0, MAX_TILE_SIZE);
        let inverted = self.switch(t, "inverted");
        let (horizontal_scale, vertical_scale, border_width) = self.scales(t)?;
        Some(TileKind::PyramidSlope {
            slope: slope?,
            platform_width: platform_width?,
            border_width,
            inverted: inverted?,
            horizontal_scale,
            vertical_scale,
        })
    }

    fn random_uniform(&mut self, t: &Section) -> Option<TileKind> {
        let noise = self.span(t, "noise", (0.02, 0.1), -MAX_TILE_SIZE, MAX_TILE_SIZE);
        let noise_step = self.positive(t, "noise_step", 0.005, MAX_TILE_SIZE);
        let scale_with_difficulty = self.switch(t, "scale_with_difficulty");
        let (horizontal_scale, vertical_scale, border_width) = self.scales(t)?;
        Some(TileKind::RandomUniform {
            noise: noise?,
            noise_step: noise_step?,
            border_width,
            horizontal_scale,
            vertical_scale,
            scale_with_difficulty: scale_with_difficulty?,
        })
    }

    /// `[reset.<name>] kind = "terrain_origin"`: spawn on a tile of `[terrain]`.
    pub(super) fn terrain_origin(
        &mut self,
        s: &Section,
        terrain: Option<&Terrain>,
    ) -> Option<ResetStep> {
        let Some(terrain) = terrain else {
            if self.spec.terrain.is_some() {
                // The terrain's own errors are reported; no second one here.
                return None;
            }
            self.d.push(
                Diagnostic::new(
                    Code::E0162,
                    format!(
                        "[reset.{}]: a terrain_origin reset needs a [terrain]",
                        s.name
                    ),
                )
                .at(s.name_loc.clone())
                .label("spawns on a tile of [terrain]"),
            );
            return None;
        };
        let joint = self.root_joint(s, "terrain_origin")?;
        let last = terrain.rows - 1;
        let rows = match s.get("rows") {
            None => (0, last),
            Some(v) => {
                let (lo, hi) = self.range(v, &format!("reset.{}.rows", s.name))?;
                let whole = lo.fract() == 0.0 && hi.fract() == 0.0;
                if !(whole && lo >= 0.0 && lo <= hi && hi <= last as f64) {
                    self.e0105(
                        v,
                        format!(
                            "[reset.{}] rows = [{lo}, {hi}] is not a range of the terrain's rows 0 … {last}",
                            s.name
                        ),
                        &format!("expected [low, high], whole numbers with 0 ≤ low ≤ high ≤ {last}"),
                    );
                    return None;
                }
                (lo as usize, hi as usize)
            }
        };
        Some(super::keyframes::root_step(
            s,
            &joint,
            3,
            Distribution::TerrainOrigin { rows },
        ))
    }
}

fn section_name(s: &Section) -> String {
    if s.name == "terrain" {
        "terrain".to_string()
    } else {
        format!("terrain.{}", s.name)
    }
}

/// The geoms one tile of a generator makes (as `envc::terrain` builds them), in floating point so
/// that a tiny step width cannot overflow the count.
fn tile_geoms(kind: &TileKind, size: [f64; 2]) -> f64 {
    match *kind {
        TileKind::PyramidStairs {
            step_width,
            platform_width,
            border_width,
            ..
        } => {
            let side =
                |x: f64| ((x - 2.0 * border_width - platform_width) / (2.0 * step_width)).trunc();
            let steps = side(size[0]).min(side(size[1])).max(0.0);
            4.0 * steps + 1.0 + if border_width > 0.0 { 4.0 } else { 0.0 }
        }
        _ => 1.0,
    }
}

/// The integer height levels a heightfield tile needs at its most difficult, and the key that
/// sets them (None for box tiles).
fn tile_levels(kind: &TileKind, size: [f64; 2]) -> Option<(f64, [&'static str; 2])> {
    match *kind {
        TileKind::PyramidSlope {
            slope,
            vertical_scale,
            ..
        } => {
            let steepest = slope.0.abs().max(slope.1.abs());
            Some((
                steepest * size[0] / 2.0 / vertical_scale,
                ["slope", "vertical_scale"],
            ))
        }
        TileKind::RandomUniform {
            noise,
            noise_step,
            vertical_scale,
            ..
        } => {
            let (lo, hi) = (noise.0 / vertical_scale, noise.1 / vertical_scale);
            let step = (noise_step / vertical_scale).trunc().max(1.0);
            let count = (hi.trunc() - lo.trunc()) / step + 1.0;
            if lo.abs().max(hi.abs()) > count {
                Some((lo.abs().max(hi.abs()), ["vertical_scale", "noise"]))
            } else {
                Some((count, ["noise_step", "vertical_scale"]))
            }
        }
        _ => None,
    }
}
