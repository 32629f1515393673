//! The terrain's pure helpers on inputs small enough to check by hand. Sizes are powers of two
//! (0.125, 0.0625, ...) so every product below is exact and compared with `==`; the formulas are
//! docs/spec-reference.md §21 and mjlab's, as the code transcribes them. Draws are compared with
//! numpy 2.4 (`numpy.random.default_rng`), the reference the layout follows.

use envspec::ir::{Terrain, TerrainTile, TileKind};

use super::*;

fn terrain(rows: usize, cols: usize, curriculum: bool, tiles: Vec<TileKind>) -> Terrain {
    Terrain {
        tile_size: [8.0, 8.0],
        rows,
        cols,
        border_width: 0.0,
        border_height: 1.0,
        seed: 0,
        curriculum,
        difficulty: (0.0, 1.0),
        tiles: tiles
            .into_iter()
            .enumerate()
            .map(|(i, kind)| TerrainTile {
                name: format!("t{i}"),
                proportion: 1.0,
                kind,
            })
            .collect(),
    }
}

fn boxes(g: &[TerrainGeom]) -> Vec<&TerrainBox> {
    g.iter()
        .map(|g| match g {
            TerrainGeom::Box(b) => b,
            TerrainGeom::Field(_) => panic!("a heightfield where a box was expected"),
        })
        .collect()
}

fn only_field(g: &Generated) -> &TerrainField {
    match &g.geoms[..] {
        [TerrainGeom::Field(f)] => f,
        other => panic!("expected one heightfield, got {other:?}"),
    }
}

fn stairs_kind(h: f64, inverted: bool) -> TileKind {
    TileKind::PyramidStairs {
        step_height: (h, h),
        step_width: 0.5,
        platform_width: 2.0,
        border_width: 1.0,
        inverted,
    }
}

#[test]
fn flat_tiles_are_centred_on_the_origin_row_major() {
    // 2 × 3 tiles of 8 m: corners at x = -8 + 8·row, y = -12 + 8·col; a flat tile's origin is
    // its centre (corner + 4), its box the 1 m slab under z = 0.
    let g = generate(&terrain(2, 3, false, vec![TileKind::Flat]));
    assert_eq!(g.tiles, [0; 6]);
    assert_eq!(
        g.origins,
        [
            [-4.0, -8.0, 0.0],
            [-4.0, 0.0, 0.0],
            [-4.0, 8.0, 0.0],
            [4.0, -8.0, 0.0],
            [4.0, 0.0, 0.0],
            [4.0, 8.0, 0.0],
        ]
    );
    let b = boxes(&g.geoms);
    assert_eq!(b.len(), 6);
    for (b, o) in b.iter().zip(&g.origins) {
        assert_eq!(b.pos, [o[0], o[1], -0.5]);
        assert_eq!(b.size, [4.0, 4.0, 0.5]);
    }
}

#[test]
fn the_border_frames_the_grid() {
    // Grid 16 × 24 m, border 2 m wide and 1 m deep: outer 20 × 28, centred at z = -0.5.
    let mut t = terrain(2, 3, false, vec![TileKind::Flat]);
    t.border_width = 2.0;
    let g = generate(&t);
    assert_eq!(g.geoms.len(), 6 + 4);
    let b = boxes(&g.geoms[6..]);
    // Along x, full outer length, at y = ±(12 + 1); along y, the inner length, at x = ±(8 + 1).
    assert_eq!((b[0].pos, b[0].size), ([0.0, 13.0, -0.5], [10.0, 1.0, 0.5]));
    assert_eq!(
        (b[1].pos, b[1].size),
        ([0.0, -13.0, -0.5], [10.0, 1.0, 0.5])
    );
    assert_eq!((b[2].pos, b[2].size), ([-9.0, 0.0, -0.5], [1.0, 12.0, 0.5]));
    assert_eq!((b[3].pos, b[3].size), ([9.0, 0.0, -0.5], [1.0, 12.0, 0.5]));
}

#[test]
fn pyramid_stairs_by_hand() {
    // One 8 m tile, frame 1 m, step 0.5 m deep and h = 0.125 high, platform 2 m:
    // int((8 - 2·1 - 2) / (2·0.5)) = 4 steps; the platform's top is (4 + 1)·h = 0.625.
    let g = generate(&terrain(1, 1, true, vec![stairs_kind(0.125, false)]));
    assert_eq!(g.origins, [[0.0, 0.0, 0.625]]);
    // frame (4) + 4 rings of 4 boxes + the platform.
    assert_eq!(g.geoms.len(), 4 + 16 + 1);
    let b = boxes(&g.geoms);
    // The frame: at least 5 cm thick (h = 0.125 is more), its top at z = 0; tile corner (-4, -4).
    assert_eq!(
        (b[0].pos, b[0].size),
        ([0.0, 3.5, -0.0625], [4.0, 0.5, 0.0625])
    );
    assert_eq!(
        (b[2].pos, b[2].size),
        ([-3.5, 0.0, -0.0625], [0.5, 3.0, 0.0625])
    );
    // Ring k is 6 - 2·0.5·k wide, its top at (k + 1)·h, its boxes 0.5 m deep.
    assert_eq!(
        (b[4].pos, b[4].size),
        ([0.0, 2.75, 0.0], [3.0, 0.25, 0.125])
    );
    assert_eq!(
        (b[5].pos, b[5].size),
        ([0.0, -2.75, 0.0], [3.0, 0.25, 0.125])
    );
    assert_eq!(
        (b[6].pos, b[6].size),
        ([2.75, 0.0, 0.0], [0.25, 2.5, 0.125])
    );
    assert_eq!(
        (b[7].pos, b[7].size),
        ([-2.75, 0.0, 0.0], [0.25, 2.5, 0.125])
    );
    for k in 0..4 {
        let ring = &b[4 + 4 * k..8 + 4 * k];
        let top = (k as f64 + 1.0) * 0.125;
        let side = 3.0 - 0.5 * k as f64;
        assert!(ring.iter().all(|b| b.pos[2] + b.size[2] == top), "ring {k}");
        assert_eq!(ring[0].size[0], side, "ring {k}");
        assert_eq!(ring[0].pos[1], side - 0.25, "ring {k}");
    }
    // The platform: 2 × 2 m, from z = -0.125 up to the origin's height.
    let p = b[20];
    assert_eq!((p.pos, p.size), ([0.0, 0.0, 0.25], [1.0, 1.0, 0.375]));
    assert_eq!(p.pos[2] + p.size[2], 0.625);
}

#[test]
fn inverted_stairs_go_down_to_the_pit_floor() {
    // The same tile upside down: the origin is the pit's floor at -(4 + 1)·h.
    let g = generate(&terrain(1, 1, true, vec![stairs_kind(0.125, true)]));
    assert_eq!(g.origins, [[0.0, 0.0, -0.625]]);
    let b = boxes(&g.geoms);
    // Ring k's top is at -(k + 1)·h, each box reaching down to the pit's bottom -(n + 1)·h.
    for k in 0..4 {
        let ring = &b[4 + 4 * k..8 + 4 * k];
        let top = -(k as f64 + 1.0) * 0.125;
        assert!(ring.iter().all(|b| b.pos[2] + b.size[2] == top), "ring {k}");
        assert!(
            ring.iter().all(|b| b.pos[2] - b.size[2] == -0.625),
            "ring {k}"
        );
    }
    // The floor: h thick, its top at the origin.
    let p = b[20];
    assert_eq!((p.pos, p.size), ([0.0, 0.0, -0.6875], [1.0, 1.0, 0.0625]));
}

#[test]
fn the_curriculum_raises_the_difficulty_along_the_rows() {
    // Row r of 3 gets difficulty r / 2: step height 0, 0.125, 0.25 for a [0, 0.25] range, so the
    // platform (5 steps' height: 4 steps + 1) is at 0, 0.625, 1.25. Column c is generator c.
    let stairs = TileKind::PyramidStairs {
        step_height: (0.0, 0.25),
        step_width: 0.5,
        platform_width: 2.0,
        border_width: 1.0,
        inverted: false,
    };
    let g = generate(&terrain(3, 2, true, vec![stairs, TileKind::Flat]));
    assert_eq!(g.tiles, [0, 1, 0, 1, 0, 1]);
    let z: Vec<f64> = g.origins.iter().map(|o| o[2]).collect();
    assert_eq!(z, [0.0, 0.0, 0.625, 0.0, 1.25, 0.0]);
    // Tile centres: x = -12 + 4 + 8·row, y = -8 + 4 + 8·col.
    assert_eq!(g.origins[5][..2], [8.0, 4.0]);
    assert_eq!(g.origins[0][..2], [-8.0, -4.0]);
}

#[test]
fn a_random_layout_draws_as_numpy() {
    // numpy 2.4: rng = default_rng(7); [(rng.choice(2, p=[.25, .75]), rng.uniform(0, 1))
    // for _ in range(6)] gives generators 1, 1, 1, 0, 1, 1 (uniform 0.897…, 0.225…, …).
    let mut t = terrain(2, 3, false, vec![TileKind::Flat, stairs_kind(0.125, false)]);
    t.seed = 7;
    t.tiles[1].proportion = 3.0;
    let g = generate(&t);
    assert_eq!(g.tiles, [1, 1, 1, 0, 1, 1]);
    // Stairs spawn on their platform, flat tiles at z = 0.
    let z: Vec<f64> = g.origins.iter().map(|o| o[2]).collect();
    assert_eq!(z, [0.625, 0.625, 0.625, 0.0, 0.625, 0.625]);
}

#[test]
fn choice_and_sums_follow_numpy() {
    // numpy 2.4: rng = default_rng(42); [rng.choice(3, p=[.2, .3, .5]) for _ in range(12)].
    let mut rng = NumpyRng::from_seed(42);
    let drawn: Vec<usize> = (0..12)
        .map(|_| choice(&mut rng, &[0.2, 0.3, 0.5]))
        .collect();
    assert_eq!(drawn, [2, 1, 2, 2, 0, 2, 2, 2, 0, 1, 1, 2]);
    // np.sum pairs eight partial sums from 8 entries on: np.sum([0.1] * 10) == 1.0 where a
    // left-to-right loop gives 0.9999999999999999; np.sum([1e16] + [1.0] * 8 + [-1e16]) == 8.0
    // (a loop: 0.0). Below 8 entries numpy loops: 0.1 + 0.2 + 0.3 == 0.6000000000000001.
    assert_eq!(numpy_sum(&[0.1; 10]), 1.0);
    let mut a = vec![1e16];
    a.extend([1.0; 8]);
    a.push(-1e16);
    assert_eq!(numpy_sum(&a), 8.0);
    assert_eq!(numpy_sum(&[0.1, 0.2, 0.3]), 0.6000000000000001);
    assert_eq!(normalized(&[1.0, 1.0, 2.0]), [0.25, 0.25, 0.5]);
}

/// The pyramid of `slope_grid` for an 8 × 8 grid of 0.125 m cells, slope 1, vertical scale
/// 0.0625, platform 0.25 m: height_max = int(1 · 1 / 2 / 0.0625) = 8, the ramp along a side is
/// (4 - |4 - i|) / 4 = 0, .25, .5, .75, 1, .75, .5, .25, a cell is 8 · ramp(i) · ramp(j) clamped
/// to the platform's height 8 · .75 · .75 = 4.5 (the cell at 4 - int(0.25 / 0.125 / 2) = 3), then
/// rounded half to even (0.5 → 0, 1.5 → 2, 4.5 → 4).
const PYRAMID: [[i64; 8]; 8] = [
    [0, 0, 0, 0, 0, 0, 0, 0],
    [0, 0, 1, 2, 2, 2, 1, 0],
    [0, 1, 2, 3, 4, 3, 2, 1],
    [0, 2, 3, 4, 4, 4, 3, 2],
    [0, 2, 4, 4, 4, 4, 4, 2],
    [0, 2, 3, 4, 4, 4, 3, 2],
    [0, 1, 2, 3, 4, 3, 2, 1],
    [0, 0, 1, 2, 2, 2, 1, 0],
];

fn slope_kind(inverted: bool) -> TileKind {
    TileKind::PyramidSlope {
        slope: (1.0, 1.0),
        platform_width: 0.25,
        border_width: 0.0,
        inverted,
        horizontal_scale: 0.125,
        vertical_scale: 0.0625,
    }
}

#[test]
fn pyramid_slope_heights_by_hand() {
    let g = slope_grid([1.0, 1.0], 1.0, 0.25, 0.0, 0.125, 0.0625);
    assert_eq!((g.w, g.l), (8, 8));
    assert_eq!(g.z, PYRAMID.concat());
    // As a 1 m tile: heights normalized by the range 4 (top 4 · 0.0625 = 0.25 m), the origin on
    // the platform, the field centred on the tile (here the world origin).
    let mut t = terrain(1, 1, true, vec![slope_kind(false)]);
    t.tile_size = [1.0, 1.0];
    let g = generate(&t);
    let f = only_field(&g);
    assert_eq!((f.nrow, f.ncol), (8, 8));
    assert_eq!(f.size, [0.5, 0.5, 0.25, 0.25]);
    assert_eq!(f.pos, [0.0, 0.0, 0.0]);
    let expect: Vec<f32> = PYRAMID.concat().iter().map(|&z| z as f32 / 4.0).collect();
    assert_eq!(f.data, expect);
    assert_eq!(g.origins, [[0.0, 0.0, 0.25]]);
    // Symmetric in x and y.
    for i in 0..8 {
        for j in 0..8 {
            assert_eq!(f.data[i * 8 + j], f.data[j * 8 + i]);
        }
    }
}

#[test]
fn an_inverted_slope_is_the_pit_of_the_same_heights() {
    let mut t = terrain(1, 1, true, vec![slope_kind(true)]);
    t.tile_size = [1.0, 1.0];
    let g = generate(&t);
    let f = only_field(&g);
    // Heights -z normalized from -4: 1 - z / 4; the field sits 0.25 m down, the origin at its
    // bottom.
    let expect: Vec<f32> = PYRAMID
        .concat()
        .iter()
        .map(|&z| 1.0 - z as f32 / 4.0)
        .collect();
    assert_eq!(f.data, expect);
    assert_eq!(f.pos, [0.0, 0.0, -0.25]);
    assert_eq!(g.origins, [[0.0, 0.0, -0.25]]);
}

#[test]
fn random_uniform_with_one_level_and_a_border() {
    // noise [0.125, 0.125] in steps of 0.0625 m: one level, 0.125 / 0.0625 = 2 units, drawn
    // everywhere inside a one-cell border (1 m / 0.125 = 8 cells, 6 inside) of height 0.
    let kind = TileKind::RandomUniform {
        noise: (0.125, 0.125),
        noise_step: 0.0625,
        border_width: 0.125,
        horizontal_scale: 0.125,
        vertical_scale: 0.0625,
        scale_with_difficulty: false,
    };
    let mut t = terrain(1, 1, true, vec![kind]);
    t.tile_size = [1.0, 1.0];
    let g = generate(&t);
    let f = only_field(&g);
    assert_eq!((f.nrow, f.ncol), (8, 8));
    // Range 2 units: top 0.125 m; the spawn height is the middle of the noise range, 0.125.
    assert_eq!(f.size, [0.5, 0.5, 0.125, 0.125]);
    for i in 0..8 {
        for j in 0..8 {
            let inside = (1..7).contains(&i) && (1..7).contains(&j);
            assert_eq!(
                f.data[i * 8 + j],
                if inside { 1.0 } else { 0.0 },
                "({i}, {j})"
            );
        }
    }
    assert_eq!(g.origins, [[0.0, 0.0, 0.125]]);
}

#[test]
fn a_level_field_has_zero_heights() {
    // No border: every cell is the one level, max == min: data 0, range taken as 1 unit.
    let mut g = vec![];
    let grid = Grid {
        w: 2,
        l: 3,
        z: vec![5; 6],
    };
    let origin = field([1.0, 1.5], grid, 0.0625, false, Some(0.3), &mut g);
    let TerrainGeom::Field(f) = &g[0] else {
        panic!("a box")
    };
    assert_eq!(f.data, [0.0; 6]);
    assert_eq!(f.size, [0.5, 0.75, 0.0625, 0.0625]);
    assert_eq!((f.nrow, f.ncol), (2, 3));
    assert_eq!(origin, [0.5, 0.75, 0.3]);
}
