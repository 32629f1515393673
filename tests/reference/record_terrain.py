"""Record mjlab 1.6.0's terrain generator for tests/terrain.rs: the geoms (type, position, size),
heightfields (size, rows, columns, heights) and spawn origins it makes for two configurations.

mjlab is not in the project venv (it needs torch and warp); its terrain modules need only mujoco
and numpy, so they are imported from the unpacked wheel without mjlab's package __init__:

    pip download mjlab==1.6.0 --no-deps -d /tmp/mjlab && unzip -q /tmp/mjlab/*.whl -d /tmp/mjlab/x
    .venv/bin/python tests/reference/record_terrain.py --mjlab /tmp/mjlab/x/mjlab

Writes tests/fixtures/terrain/{rough_curriculum,random_layout}.npz.
"""

from __future__ import annotations

import argparse
import sys
import types
from pathlib import Path

import numpy as np

OUT = Path(__file__).resolve().parents[1] / "fixtures" / "terrain"


def load_mjlab(root: str):
    # Package stubs so that `mjlab/__init__.py` (torch, warp, tyro) is not run.
    for name, path in [("mjlab", root), ("mjlab.terrains", root + "/terrains")]:
        pkg = types.ModuleType(name)
        pkg.__path__ = [path]
        sys.modules[name] = pkg
    import mjlab.terrains.heightfield_terrains as hf
    import mjlab.terrains.primitive_terrains as prim
    import mjlab.terrains.terrain_generator as gen

    return gen, prim, hf


def record(gen, cfg, name: str) -> None:
    import mujoco

    tiles: list[int] = []
    original = gen.TerrainGenerator._create_terrain_geom

    def counted(self, spec, *args, **kwargs):
        before = len(spec.body("terrain").geoms)
        out = original(self, spec, *args, **kwargs)
        tiles.append(len(spec.body("terrain").geoms) - before)
        return out

    gen.TerrainGenerator._create_terrain_geom = counted
    try:
        g = gen.TerrainGenerator(cfg)
        spec = mujoco.MjSpec()
        g.compile(spec)
    finally:
        gen.TerrainGenerator._create_terrain_geom = original
    geoms = spec.body("terrain").geoms
    hfields = {h.name: h for h in spec.hfields}
    geom_tile = np.concatenate([np.full(n, i) for i, n in enumerate(tiles)] + [np.full(len(geoms) - sum(tiles), -1)])
    fields = [hfields[gm.hfieldname] for gm in geoms if gm.type == mujoco.mjtGeom.mjGEOM_HFIELD]
    np.savez_compressed(
        OUT / f"{name}.npz",
        geom_type=np.array([int(gm.type) for gm in geoms], dtype=np.int64),
        geom_pos=np.array([gm.pos for gm in geoms], dtype=np.float64),
        geom_size=np.array([gm.size for gm in geoms], dtype=np.float64),
        geom_tile=geom_tile.astype(np.int64),
        hfield_size=np.array([f.size for f in fields], dtype=np.float64).reshape(-1, 4),
        hfield_shape=np.array([[f.nrow, f.ncol] for f in fields], dtype=np.int64).reshape(-1, 2),
        hfield_data=np.concatenate([np.asarray(f.userdata, dtype=np.float32) for f in fields] or [np.zeros(0, np.float32)]),
        origins=np.asarray(g.terrain_origins, dtype=np.float64).reshape(-1, 3),
    )
    print(f"{name}: {len(geoms)} geoms, {len(fields)} heightfields, {len(tiles)} tiles")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--mjlab", required=True, help="the unpacked wheel's mjlab/ directory")
    a = p.parse_args()
    gen, prim, hf = load_mjlab(a.mjlab)
    OUT.mkdir(parents=True, exist_ok=True)
    stairs = dict(step_height_range=(0.0, 0.1), step_width=0.3, platform_width=3.0, border_width=1.0)
    slope = dict(slope_range=(0.0, 1.0), platform_width=2.0, border_width=0.25)
    # specs/examples/mjlab_velocity_rough_go1.toml's [terrain]: ROUGH_TERRAINS_CFG, curriculum,
    # without wave_terrain.
    rough = gen.TerrainGeneratorCfg(
        size=(8.0, 8.0), border_width=20.0, num_rows=10, num_cols=20, curriculum=True,
        sub_terrains={
            "flat": prim.BoxFlatTerrainCfg(proportion=0.2),
            "pyramid_stairs": prim.BoxPyramidStairsTerrainCfg(proportion=0.2, **stairs),
            "pyramid_stairs_inv": prim.BoxInvertedPyramidStairsTerrainCfg(proportion=0.2, **stairs),
            "hf_pyramid_slope": hf.HfPyramidSlopedTerrainCfg(proportion=0.1, **slope),
            "hf_pyramid_slope_inv": hf.HfPyramidSlopedTerrainCfg(proportion=0.1, inverted=True, **slope),
            "random_rough": hf.HfRandomUniformTerrainCfg(
                proportion=0.1, noise_range=(0.02, 0.10), noise_step=0.02, border_width=0.25
            ),
        },
    )
    record(gen, rough, "rough_curriculum")
    # The random layout: each tile draws its generator and difficulty from default_rng(7); the
    # random_uniform tiles' draws come from the same stream.
    mixed = gen.TerrainGeneratorCfg(
        size=(6.0, 5.0), border_width=3.0, border_height=0.5, num_rows=4, num_cols=5, seed=7,
        difficulty_range=(0.2, 0.9), curriculum=False,
        sub_terrains={
            "flat": prim.BoxFlatTerrainCfg(proportion=0.1),
            "up": prim.BoxPyramidStairsTerrainCfg(proportion=0.3, step_height_range=(0.02, 0.15), step_width=0.4, platform_width=1.5, border_width=0.5),
            "down": prim.BoxInvertedPyramidStairsTerrainCfg(proportion=0.2, step_height_range=(0.02, 0.15), step_width=0.4, platform_width=1.5),
            "slope": hf.HfPyramidSlopedTerrainCfg(proportion=0.25, slope_range=(0.1, 0.6), platform_width=1.0, border_width=0.2, horizontal_scale=0.1),
            "noise": hf.HfRandomUniformTerrainCfg(proportion=0.15, noise_range=(0.0, 0.06), noise_step=0.01, border_width=0.2),
        },
    )
    record(gen, mixed, "random_layout")


if __name__ == "__main__":
    main()
