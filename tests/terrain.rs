//! `[terrain]` against mjlab 1.6.0's terrain generator, recorded by
//! `tests/reference/record_terrain.py` (`tests/fixtures/terrain/*.npz`): the same geoms in the same
//! order, bit for bit (positions, box sizes, heightfield sizes and heights), and the same spawn
//! origins, for the rough spec's curriculum layout and a random layout drawn from
//! `default_rng(7)`. `random_uniform` heights are the one documented difference (mjlab smooths its
//! draws with a bicubic spline); their count, and so every later draw, is the same.

use std::fs::File;
use std::path::{Path, PathBuf};

use envc::terrain::{Generated, TerrainGeom, generate};
use envspec::ir::{Terrain, TerrainTile, TileKind};
use ndarray::{Array1, Array2};
use ndarray_npy::NpzReader;

fn fixture(name: &str) -> NpzReader<File> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("fixtures/terrain/{name}.npz"));
    NpzReader::new(File::open(&p).expect("the terrain fixture")).expect("an npz")
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("root")
        .to_path_buf()
}

/// The rough spec's `[terrain]`, resolved from the spec file.
fn rough() -> Terrain {
    let spec = envspec::load(
        &repo().join("specs/examples/mjlab_velocity_rough_go1.toml"),
        &[],
    )
    .expect("the rough spec resolves");
    spec.model_edits.terrain.clone().expect("a [terrain]")
}

fn random_layout() -> Terrain {
    let stairs = |inverted, border_width| TileKind::PyramidStairs {
        step_height: (0.02, 0.15),
        step_width: 0.4,
        platform_width: 1.5,
        border_width,
        inverted,
    };
    let tile = |name: &str, proportion, kind| TerrainTile {
        name: name.into(),
        proportion,
        kind,
    };
    Terrain {
        tile_size: [6.0, 5.0],
        rows: 4,
        cols: 5,
        border_width: 3.0,
        border_height: 0.5,
        seed: 7,
        curriculum: false,
        difficulty: (0.2, 0.9),
        tiles: vec![
            tile("flat", 0.1, TileKind::Flat),
            tile("up", 0.3, stairs(false, 0.5)),
            tile("down", 0.2, stairs(true, 0.0)),
            tile(
                "slope",
                0.25,
                TileKind::PyramidSlope {
                    slope: (0.1, 0.6),
                    platform_width: 1.0,
                    border_width: 0.2,
                    inverted: false,
                    horizontal_scale: 0.1,
                    vertical_scale: 0.005,
                },
            ),
            tile(
                "noise",
                0.15,
                TileKind::RandomUniform {
                    noise: (0.0, 0.06),
                    noise_step: 0.01,
                    border_width: 0.2,
                    horizontal_scale: 0.1,
                    vertical_scale: 0.005,
                    scale_with_difficulty: false,
                },
            ),
        ],
    }
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// Compare one terrain with mjlab's recording.
fn check(name: &str, t: &Terrain, g: &Generated) {
    let mut npz = fixture(name);
    let types: Array1<i64> = npz.by_name("geom_type").expect("geom_type");
    let pos: Array2<f64> = npz.by_name("geom_pos").expect("geom_pos");
    let size: Array2<f64> = npz.by_name("geom_size").expect("geom_size");
    let geom_tile: Array1<i64> = npz.by_name("geom_tile").expect("geom_tile");
    let hsize: Array2<f64> = npz.by_name("hfield_size").expect("hfield_size");
    let hshape: Array2<i64> = npz.by_name("hfield_shape").expect("hfield_shape");
    let hdata: Array1<f32> = npz.by_name("hfield_data").expect("hfield_data");
    let origins: Array2<f64> = npz.by_name("origins").expect("origins");
    assert_eq!(g.geoms.len(), types.len(), "{name}: geom count");
    // Tile `k` in the order mjlab makes them: by column (curriculum) or by row.
    let tile_at = |k: usize| {
        let (row, col) = if t.curriculum {
            (k % t.rows, k / t.rows)
        } else {
            (k / t.cols, k % t.cols)
        };
        g.tiles[row * t.cols + col]
    };
    let (mut field, mut at, mut smoothed) = (0, 0, 0);
    for (i, geom) in g.geoms.iter().enumerate() {
        let want_pos = pos.row(i).to_vec();
        match geom {
            TerrainGeom::Box(b) => {
                assert_eq!(types[i], 6, "{name}: geom {i} is a box");
                assert_eq!(bits(&b.pos), bits(&want_pos), "{name}: geom {i} pos");
                assert_eq!(
                    bits(&b.size),
                    bits(&size.row(i).to_vec()),
                    "{name}: geom {i} size"
                );
            }
            TerrainGeom::Field(f) => {
                assert_eq!(types[i], 1, "{name}: geom {i} is a heightfield");
                assert_eq!(bits(&f.pos), bits(&want_pos), "{name}: geom {i} pos");
                let shape = [hshape[[field, 0]] as usize, hshape[[field, 1]] as usize];
                assert_eq!([f.nrow, f.ncol], shape, "{name}: heightfield {field} shape");
                let n = f.nrow * f.ncol;
                let kind = &t.tiles[tile_at(geom_tile[i] as usize)].kind;
                if matches!(kind, TileKind::RandomUniform { .. }) {
                    // Same extent; the heights are smoothed in mjlab.
                    assert_eq!(bits(&f.size[..2]), bits(&hsize.row(field).to_vec()[..2]));
                    smoothed += 1;
                } else {
                    assert_eq!(
                        bits(&f.size),
                        bits(&hsize.row(field).to_vec()),
                        "{name}: heightfield {field} size"
                    );
                    let want: Vec<u32> = hdata
                        .slice(ndarray::s![at..at + n])
                        .iter()
                        .map(|x| x.to_bits())
                        .collect();
                    let got: Vec<u32> = f.data.iter().map(|x| x.to_bits()).collect();
                    assert!(got == want, "{name}: heightfield {field} heights differ");
                }
                field += 1;
                at += n;
            }
        }
    }
    assert_eq!(field, hshape.nrows(), "{name}: heightfield count");
    assert!(
        field > smoothed,
        "{name}: some heightfield is compared height by height"
    );
    assert_eq!(g.origins.len(), origins.nrows());
    for (k, o) in g.origins.iter().enumerate() {
        assert_eq!(
            bits(o),
            bits(&origins.row(k).to_vec()),
            "{name}: origin of tile {k}"
        );
    }
}

#[test]
fn the_rough_specs_curriculum_terrain_is_mjlabs() {
    let t = rough();
    assert!(t.curriculum && t.rows == 10 && t.cols == 6);
    check("rough_curriculum", &t, &generate(&t));
}

#[test]
fn a_random_layout_draws_as_mjlab_does() {
    let t = random_layout();
    let g = generate(&t);
    // Every generator appears (the draws decide which where).
    assert!(
        (0..t.tiles.len()).all(|k| g.tiles.contains(&k)),
        "{:?}",
        g.tiles
    );
    check("random_layout", &t, &g);
}

#[test]
fn terrain_origin_spawns_on_a_tile_of_the_rows_asked() {
    let spec = std::sync::Arc::new(
        envspec::load(
            &repo().join("specs/examples/mjlab_velocity_rough_go1.toml"),
            &[],
        )
        .expect("the rough spec resolves"),
    );
    let g = generate(spec.model_edits.terrain.as_ref().expect("a [terrain]"));
    let mut env = envc::Env::new(spec).expect("the env builds");
    let mut rows_hit = [false; 10];
    for seed in 0..200 {
        env.reset(Some(seed));
        let (qpos, _) = env.state();
        // keyframe root (0, 0, 0.278) + the tile's origin + root_pose's x, y ∈ [-0.5, 0.5],
        // z ∈ [0.01, 0.05]
        let tile = g
            .origins
            .iter()
            .position(|o| {
                (qpos[0] - o[0]).abs() <= 0.5
                    && (qpos[1] - o[1]).abs() <= 0.5
                    && (0.278 + 0.01..=0.278 + 0.05).contains(&(qpos[2] - o[2]))
            })
            .unwrap_or_else(|| panic!("seed {seed}: the root {:?} is on no tile", &qpos[..3]));
        rows_hit[tile / 6] = true;
    }
    assert_eq!(
        rows_hit,
        [
            true, true, true, true, true, true, false, false, false, false
        ]
    );
}
