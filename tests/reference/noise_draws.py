"""Observation noise, computed independently with numpy for tests/obs_noise.rs.

Reads JSON on stdin: {"seed", "reset_draws", "segments": [{"kind", "level", "scale",
"clip": [lo, hi] | null, "raw": [[...per element...] per observation time]}]}. The env's stream is
numpy's `default_rng(seed)`; at every observation time (the reset, then each step) the noisy
segments draw in observation order, element by element (docs/spec-reference.md, "Observation
noise, delay and action latency"). The reset draws come first (`reset_draws` doubles).
Prints {"noisy": [[[IEEE bits per element, decimal strings] per time] per segment]}.
"""

import json
import struct
import sys

import numpy as np

doc = json.load(sys.stdin)
rng = np.random.default_rng(doc["seed"])
rng.random(doc["reset_draws"])  # the spec's [reset] uniforms: one double each
segs = doc["segments"]
times = len(segs[0]["raw"])
out = [[] for _ in segs]
for t in range(times):
    for j, s in enumerate(segs):
        raw = np.array(s["raw"][t], dtype=np.float64)
        n = len(raw)
        if s["kind"] == "uniform":
            # MuJoCo Playground: (2 * U(0, 1) - 1) * level * scale
            noise = (2 * rng.random(n) - 1) * s["level"] * s["scale"]
        else:
            noise = rng.standard_normal(n) * s["level"] * s["scale"]
        x = raw + noise
        if s["clip"] is not None:
            x = np.clip(x, s["clip"][0], s["clip"][1])
        out[j].append([str(struct.unpack("<Q", struct.pack("<d", v))[0]) for v in x])
print(json.dumps({"noisy": out}))
