//! `[terrain]`: a grid of generated tiles added to the world body.

/// `[terrain]`: a grid of `rows × cols` square tiles centred on the world origin, each made by
/// one generator at a difficulty, with a border around the grid (mjlab's `TerrainGenerator`,
/// whose geometry it reproduces). The runtime generates the geoms and each tile's spawn origin.
#[derive(Clone, Debug, PartialEq)]
pub struct Terrain {
    /// A tile's size along x and y, in metres.
    pub tile_size: [f64; 2],
    /// Tiles along x (difficulty grows along x in the curriculum layout).
    pub rows: usize,
    /// Tiles along y.
    pub cols: usize,
    /// Width of the flat border around the grid, in metres (0: none).
    pub border_width: f64,
    /// Depth of the border boxes below z = 0.
    pub border_height: f64,
    /// The layout's draws (`default_rng(seed)`): which generator and difficulty each tile gets in
    /// the random layout. Part of the model: the terrain is the same in every episode.
    pub seed: u64,
    /// Curriculum layout: column `c` is generator `c`, difficulty rises with the row, no draws.
    /// Otherwise each tile draws its generator (by proportion) and its difficulty.
    pub curriculum: bool,
    /// `(low, high)` of the difficulty in [0, 1].
    pub difficulty: (f64, f64),
    /// The generators, in declaration order.
    pub tiles: Vec<TerrainTile>,
}

/// One `[terrain.<name>]` generator.
#[derive(Clone, Debug, PartialEq)]
pub struct TerrainTile {
    /// The table's name.
    pub name: String,
    /// Its share of the tiles in the random layout.
    pub proportion: f64,
    /// What it builds.
    pub kind: TileKind,
}

/// The tile generators (each mjlab's of the same name; `difficulty` interpolates its ranges).
#[derive(Clone, Debug, PartialEq)]
pub enum TileKind {
    /// A flat 1 m thick box with its top at z = 0.
    Flat,
    /// Square stairs up to a central platform (`inverted`: down into a pit), from boxes.
    PyramidStairs {
        /// Step height at difficulty 0 and 1.
        step_height: (f64, f64),
        /// Depth of each step.
        step_width: f64,
        /// Side of the central platform.
        platform_width: f64,
        /// Flat frame around the stairs.
        border_width: f64,
        /// Down instead of up.
        inverted: bool,
    },
    /// A pyramid slope up to a flat top (`inverted`: down into a pit), as a heightfield.
    PyramidSlope {
        /// Slope (rise over run) at difficulty 0 and 1.
        slope: (f64, f64),
        /// Side of the flat platform.
        platform_width: f64,
        /// Flat frame around the slope.
        border_width: f64,
        /// Down instead of up.
        inverted: bool,
        /// Metres per heightfield cell.
        horizontal_scale: f64,
        /// Metres per height unit.
        vertical_scale: f64,
    },
    /// Heights drawn uniformly from `noise` in steps of `noise_step`, one per cell, as a
    /// heightfield (the difficulty scales the range when `scale_with_difficulty`).
    RandomUniform {
        /// `(low, high)` height, metres.
        noise: (f64, f64),
        /// Height quantum, metres.
        noise_step: f64,
        /// Flat frame around the noise.
        border_width: f64,
        /// Metres per heightfield cell.
        horizontal_scale: f64,
        /// Metres per height unit.
        vertical_scale: f64,
        /// Scale the noise range by the difficulty.
        scale_with_difficulty: bool,
    },
}
