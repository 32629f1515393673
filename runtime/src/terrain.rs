//! `[terrain]` made into geoms: a grid of tiles centred on the world origin, each tile's boxes or
//! heightfield, a border around the grid, and each tile's spawn origin.
//!
//! The layout, the box generators and the pyramid slope follow mjlab 1.6.0's terrain generator
//! formula for formula, in the same order and with the same float operations, so the geoms and
//! origins are its own (checked against a recording of mjlab, `tests/terrain.rs`). The random
//! layout draws from `numpy.random.default_rng(seed)` as mjlab does. One difference:
//! `random_uniform` uses its drawn heights at the nearest sample where mjlab interpolates them with
//! scipy's bicubic spline (its draws are the same, so the tiles after it match).

use envspec::ir::{Terrain, TileKind};

use crate::rng::NumpyRng;

#[cfg(test)]
mod tests;

/// The thinnest border of a stairs tile (mjlab's `_MIN_BORDER_HEIGHT`).
const MIN_BORDER_HEIGHT: f64 = 0.05;

/// A box geom: centre and half sizes (world frame).
#[derive(Clone, Debug, PartialEq)]
pub struct TerrainBox {
    /// Centre.
    pub pos: [f64; 3],
    /// Half sizes.
    pub size: [f64; 3],
}

/// A heightfield geom and its field.
#[derive(Clone, Debug, PartialEq)]
pub struct TerrainField {
    /// The geom's position (world frame).
    pub pos: [f64; 3],
    /// `hfield_size`: x and y half extents, the height of 1.0, the base depth.
    pub size: [f64; 4],
    /// Rows (along x, as mjlab passes them).
    pub nrow: usize,
    /// Columns.
    pub ncol: usize,
    /// Heights in [0, 1], row-major.
    pub data: Vec<f32>,
}

/// One geom of the terrain, in the order mjlab adds them.
#[derive(Clone, Debug, PartialEq)]
pub enum TerrainGeom {
    /// A box.
    Box(TerrainBox),
    /// A heightfield.
    Field(TerrainField),
}

/// The generated terrain.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Generated {
    /// The geoms: tile by tile (layout order), then the border's four boxes.
    pub geoms: Vec<TerrainGeom>,
    /// Each tile's spawn origin, row-major (`row * cols + col`).
    pub origins: Vec<[f64; 3]>,
    /// Each tile's generator (an index into `Terrain::tiles`), row-major.
    pub tiles: Vec<usize>,
}

/// Build the terrain of a spec.
pub fn generate(t: &Terrain) -> Generated {
    let mut rng = NumpyRng::from_seed(t.seed);
    let mut g = Generated {
        geoms: vec![],
        origins: vec![[0.0; 3]; t.rows * t.cols],
        tiles: vec![0; t.rows * t.cols],
    };
    let (lo, hi) = t.difficulty;
    let tile = |g: &mut Generated, rng: &mut NumpyRng, row: usize, col: usize, k: usize, d: f64| {
        let corner = [
            -(t.rows as f64) * t.tile_size[0] * 0.5 + row as f64 * t.tile_size[0],
            -(t.cols as f64) * t.tile_size[1] * 0.5 + col as f64 * t.tile_size[1],
            0.0,
        ];
        let start = g.geoms.len();
        let origin = build_tile(&t.tiles[k].kind, t.tile_size, d, rng, &mut g.geoms);
        for geom in &mut g.geoms[start..] {
            let pos = match geom {
                TerrainGeom::Box(b) => &mut b.pos,
                TerrainGeom::Field(f) => &mut f.pos,
            };
            for (p, c) in pos.iter_mut().zip(corner) {
                *p += c;
            }
        }
        g.tiles[row * t.cols + col] = k;
        g.origins[row * t.cols + col] = [
            origin[0] + corner[0],
            origin[1] + corner[1],
            origin[2] + corner[2],
        ];
    };
    if t.curriculum {
        // One column per generator; the difficulty rises along the rows; no draws.
        for col in 0..t.cols {
            for row in 0..t.rows {
                let s = row as f64 / (t.rows.max(2) - 1) as f64;
                tile(&mut g, &mut rng, row, col, col, lo + (hi - lo) * s);
            }
        }
    } else {
        let p = normalized(&t.tiles.iter().map(|x| x.proportion).collect::<Vec<_>>());
        for index in 0..t.rows * t.cols {
            let (row, col) = (index / t.cols, index % t.cols);
            let k = choice(&mut rng, &p);
            let d = rng.uniform(lo, hi);
            tile(&mut g, &mut rng, row, col, k, d);
        }
    }
    if t.border_width > 0.0 {
        let inner = [
            t.rows as f64 * t.tile_size[0],
            t.cols as f64 * t.tile_size[1],
        ];
        let outer = [
            inner[0] + 2.0 * t.border_width,
            inner[1] + 2.0 * t.border_width,
        ];
        border(
            &mut g.geoms,
            outer,
            inner,
            t.border_height,
            [0.0, 0.0, -t.border_height / 2.0],
        );
    }
    g
}

/// `proportions / np.sum(proportions)`, with numpy's summation order (pairwise in blocks of 8).
fn normalized(p: &[f64]) -> Vec<f64> {
    let total = numpy_sum(p);
    p.iter().map(|x| x / total).collect()
}

/// numpy's `sum` of a float64 array of up to 128 entries: a plain loop below 8, else eight
/// interleaved partial sums combined pairwise, then the tail.
fn numpy_sum(a: &[f64]) -> f64 {
    if a.len() < 8 {
        return a.iter().fold(0.0, |s, x| s + x);
    }
    let mut r = [0.0; 8];
    r.copy_from_slice(&a[..8]);
    let whole = a.len() - a.len() % 8;
    for chunk in a[8..whole].chunks_exact(8) {
        for (r, x) in r.iter_mut().zip(chunk) {
            *r += x;
        }
    }
    let mut s = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
    for x in &a[whole..] {
        s += x;
    }
    s
}

/// numpy `Generator.choice(len(p), p=p)`: one `random()` draw against the normalized cumulative
/// sum, searched from the right.
fn choice(rng: &mut NumpyRng, p: &[f64]) -> usize {
    let mut cdf: Vec<f64> = Vec::with_capacity(p.len());
    let mut acc = 0.0;
    for x in p {
        acc += x;
        cdf.push(acc);
    }
    let last = acc;
    for c in &mut cdf {
        *c /= last;
    }
    let u = rng.next_f64();
    cdf.iter().position(|&c| c > u).unwrap_or(p.len() - 1)
}

/// The geoms of one tile in its own frame (corner at the origin); returns the spawn origin.
fn build_tile(
    kind: &TileKind,
    size: [f64; 2],
    d: f64,
    rng: &mut NumpyRng,
    out: &mut Vec<TerrainGeom>,
) -> [f64; 3] {
    match *kind {
        TileKind::Flat => {
            out.push(boxed(
                [size[0] / 2.0, size[1] / 2.0, 0.0 - 1.0 / 2.0],
                [size[0] / 2.0, size[1] / 2.0, 1.0 / 2.0],
            ));
            [size[0] / 2.0, size[1] / 2.0, 0.0]
        }
        TileKind::PyramidStairs {
            step_height,
            step_width,
            platform_width,
            border_width,
            inverted,
        } => {
            let h = step_height.0 + d * (step_height.1 - step_height.0);
            stairs(
                size,
                h,
                step_width,
                platform_width,
                border_width,
                inverted,
                out,
            )
        }
        TileKind::PyramidSlope {
            slope,
            platform_width,
            border_width,
            inverted,
            horizontal_scale,
            vertical_scale,
        } => {
            let s = if inverted {
                -slope.0 - d * (slope.1 - slope.0)
            } else {
                slope.0 + d * (slope.1 - slope.0)
            };
            let grid = slope_grid(
                size,
                s,
                platform_width,
                border_width,
                horizontal_scale,
                vertical_scale,
            );
            field(size, grid, vertical_scale, inverted, None, out)
        }
        TileKind::RandomUniform {
            noise,
            noise_step,
            border_width,
            horizontal_scale,
            vertical_scale,
            scale_with_difficulty,
        } => {
            let scale = if scale_with_difficulty { d } else { 1.0 };
            let (lo, hi) = (noise.0 * scale, noise.1 * scale);
            let grid = uniform_grid(
                size,
                (lo, hi),
                noise_step,
                border_width,
                horizontal_scale,
                vertical_scale,
                rng,
            );
            field(
                size,
                grid,
                vertical_scale,
                false,
                Some((lo + hi) / 2.0),
                out,
            )
        }
    }
}

fn boxed(pos: [f64; 3], size: [f64; 3]) -> TerrainGeom {
    TerrainGeom::Box(TerrainBox { pos, size })
}

/// mjlab's `make_border`: four boxes around `inner` within `outer`, centred on `c`.
fn border(out: &mut Vec<TerrainGeom>, outer: [f64; 2], inner: [f64; 2], height: f64, c: [f64; 3]) {
    let tx = (outer[0] - inner[0]) / 2.0;
    let ty = (outer[1] - inner[1]) / 2.0;
    let half = |d: [f64; 3]| [d[0] / 2.0, d[1] / 2.0, d[2] / 2.0];
    let dims = [outer[0], ty, height];
    out.push(boxed(
        [c[0], c[1] + inner[1] / 2.0 + ty / 2.0, c[2]],
        half(dims),
    ));
    out.push(boxed(
        [c[0], c[1] - inner[1] / 2.0 - ty / 2.0, c[2]],
        half(dims),
    ));
    let dims = [tx, inner[1], height];
    out.push(boxed(
        [c[0] - inner[0] / 2.0 - tx / 2.0, c[1], c[2]],
        half(dims),
    ));
    out.push(boxed(
        [c[0] + inner[0] / 2.0 + tx / 2.0, c[1], c[2]],
        half(dims),
    ));
}

/// Half sizes at least 1e-6 (mjlab's `safe_size`: MuJoCo refuses a zero size).
fn safe(d: [f64; 3]) -> [f64; 3] {
    [
        (d[0] / 2.0).max(1e-6),
        (d[1] / 2.0).max(1e-6),
        (d[2] / 2.0).max(1e-6),
    ]
}

/// mjlab's `BoxPyramidStairsTerrainCfg` and `BoxInvertedPyramidStairsTerrainCfg`.
fn stairs(
    size: [f64; 2],
    h: f64,
    sw: f64,
    platform: f64,
    bw: f64,
    inverted: bool,
    out: &mut Vec<TerrainGeom>,
) -> [f64; 3] {
    // Python's `int()` of the quotient: truncation toward zero.
    let nx = ((size[0] - 2.0 * bw - platform) / (2.0 * sw)) as i64;
    let ny = ((size[1] - 2.0 * bw - platform) / (2.0 * sw)) as i64;
    let n = nx.min(ny).max(0) as usize;
    let total = (n as f64 + 1.0) * h;
    if bw > 0.0 {
        let bh = h.max(MIN_BORDER_HEIGHT);
        let c = [
            0.5 * size[0],
            0.5 * size[1],
            if inverted { -0.5 * bh } else { -bh / 2.0 },
        ];
        border(out, size, [size[0] - 2.0 * bw, size[1] - 2.0 * bw], bh, c);
    }
    let center = [0.5 * size[0], 0.5 * size[1], 0.0];
    let ts = [size[0] - 2.0 * bw, size[1] - 2.0 * bw];
    for k in 0..n {
        let kf = k as f64;
        let bs = [ts[0] - 2.0 * kf * sw, ts[1] - 2.0 * kf * sw];
        let (z, height) = if inverted {
            (
                center[2] - total / 2.0 - (kf + 1.0) * h / 2.0,
                total - (kf + 1.0) * h,
            )
        } else {
            (center[2] + kf * h / 2.0, (kf + 2.0) * h)
        };
        let off = (kf + 0.5) * sw;
        let s = safe([bs[0], sw, height]);
        out.push(boxed([center[0], center[1] + ts[1] / 2.0 - off, z], s));
        out.push(boxed([center[0], center[1] - ts[1] / 2.0 + off, z], s));
        let s = safe([sw, bs[1] - 2.0 * sw, height]);
        out.push(boxed([center[0] + ts[0] / 2.0 - off, center[1], z], s));
        out.push(boxed([center[0] - ts[0] / 2.0 + off, center[1], z], s));
    }
    let nf = n as f64;
    let middle = [ts[0] - 2.0 * nf * sw, ts[1] - 2.0 * nf * sw];
    if inverted {
        out.push(boxed(
            [center[0], center[1], center[2] - total - h / 2.0],
            safe([middle[0], middle[1], h]),
        ));
        [center[0], center[1], -(nf + 1.0) * h]
    } else {
        out.push(boxed(
            [center[0], center[1], center[2] + nf * h / 2.0],
            safe([middle[0], middle[1], (nf + 2.0) * h]),
        ));
        [center[0], center[1], (nf + 1.0) * h]
    }
}

/// An integer height grid, `w × l` (x-major), and the inner region a border leaves.
struct Grid {
    w: usize,
    l: usize,
    z: Vec<i64>,
}

/// Cells of a tile side and of its border (Python's `int()` of the quotients).
fn pixels(size: [f64; 2], hs: f64, bw: f64) -> (usize, usize, usize) {
    (
        (size[0] / hs) as usize,
        (size[1] / hs) as usize,
        (bw / hs) as usize,
    )
}

/// mjlab's `HfPyramidSlopedTerrainCfg` heights.
fn slope_grid(size: [f64; 2], s: f64, platform: f64, bw: f64, hs: f64, vs: f64) -> Grid {
    let (w, l, b) = pixels(size, hs, bw);
    let (iw, il) = (w.saturating_sub(2 * b), l.saturating_sub(2 * b));
    let mut z = vec![0i64; w * l];
    // The side over which the slope rises: the inner width with a border, else the tile's.
    let run = if b > 0 { iw as f64 * hs } else { size[0] };
    let height_max = (s * run / 2.0 / vs) as i64 as f64;
    let (cx, cy) = ((iw as f64 / 2.0) as i64, (il as f64 / 2.0) as i64);
    let ramp = |c: i64, i: usize| {
        if c == 0 {
            0.0
        } else {
            (c - (c - i as i64).abs()) as f64 / c as f64
        }
    };
    let raw = |i: usize, j: usize| height_max * ramp(cx, i) * ramp(cy, j);
    let p = (platform / hs / 2.0) as i64;
    let (xp, yp) = ((iw / 2) as i64 - p, (il / 2) as i64 - p);
    let zp = if xp >= 0 && yp >= 0 && (xp as usize) < iw && (yp as usize) < il {
        raw(xp as usize, yp as usize)
    } else {
        0.0
    };
    let (lo, hi) = (zp.min(0.0), zp.max(0.0));
    for i in 0..iw {
        for j in 0..il {
            z[(i + b) * l + j + b] = raw(i, j).clamp(lo, hi).round_ties_even() as i64;
        }
    }
    Grid { w, l, z }
}

/// Heights drawn uniformly from `noise` in steps (mjlab's `HfRandomUniformTerrainCfg` draws),
/// used at the nearest sample instead of mjlab's bicubic spline.
fn uniform_grid(
    size: [f64; 2],
    noise: (f64, f64),
    step: f64,
    bw: f64,
    hs: f64,
    vs: f64,
    rng: &mut NumpyRng,
) -> Grid {
    let (w, l, b) = pixels(size, hs, bw);
    let (iw, il) = (w.saturating_sub(2 * b), l.saturating_sub(2 * b));
    let inner = if b > 0 {
        [iw as f64 * hs, il as f64 * hs]
    } else {
        size
    };
    let (dw, dl) = ((inner[0] / hs) as usize, (inner[1] / hs) as usize);
    let (hmin, hmax, hstep) = (
        (noise.0 / vs) as i64,
        (noise.1 / vs) as i64,
        ((step / vs) as i64).max(1),
    );
    // np.arange(hmin, hmax + hstep, hstep), never materialized: its k-th entry is
    // hmin + k·hstep (envspec bounds the levels, so nothing here saturates).
    let span = hmax.saturating_sub(hmin).max(0).unsigned_abs();
    let count = i64::try_from(span.div_ceil(hstep.unsigned_abs()))
        .unwrap_or(i64::MAX - 1)
        .saturating_add(1);
    let drawn: Vec<i64> = (0..dw * dl)
        .map(|_| hmin.saturating_add(rng.integers(0, count).saturating_mul(hstep)))
        .collect();
    let near = |i: usize, n: usize, m: usize| {
        if n <= 1 || m == 0 {
            0
        } else {
            ((i as f64 * (m - 1) as f64 / (n - 1) as f64).round() as usize).min(m - 1)
        }
    };
    let mut z = vec![0i64; w * l];
    for i in 0..iw {
        for j in 0..il {
            if dw > 0 && dl > 0 {
                z[(i + b) * l + j + b] = drawn[near(i, iw, dw) * dl + near(j, il, dl)];
            }
        }
    }
    Grid { w, l, z }
}

/// A heightfield geom from an integer grid, normalized as mjlab does; returns the spawn origin
/// (`spawn`: a fixed height, else the top, or the bottom when inverted).
fn field(
    size: [f64; 2],
    g: Grid,
    vs: f64,
    inverted: bool,
    spawn: Option<f64>,
    out: &mut Vec<TerrainGeom>,
) -> [f64; 3] {
    let min = g.z.iter().copied().min().unwrap_or(0);
    let max = g.z.iter().copied().max().unwrap_or(0);
    let range = if max != min { max - min } else { 1 };
    let top = range as f64 * vs;
    let data =
        g.z.iter()
            .map(|&x| {
                if max != min {
                    ((x - min) as f64 / range as f64) as f32
                } else {
                    0.0
                }
            })
            .collect();
    let z_off = if inverted { -top } else { 0.0 };
    out.push(TerrainGeom::Field(TerrainField {
        pos: [size[0] / 2.0, size[1] / 2.0, z_off],
        size: [size[0] / 2.0, size[1] / 2.0, top, top],
        nrow: g.w,
        ncol: g.l,
        data,
    }));
    let z = spawn.unwrap_or(if inverted { z_off } else { top });
    [size[0] / 2.0, size[1] / 2.0, z]
}
