"""The resolved IR as the GPU executor reads it (`envc._envc.gpu_plan`), and the check that
refuses, with one coded error listing all of them, every part a backend cannot run."""

from __future__ import annotations

import json
from collections.abc import Collection, Iterator
from dataclasses import dataclass
from typing import Any

from .._envc import SpecError

#: The stable code of a spec the GPU executor refuses (docs/errors.md).
CODE = "E1700"

#: Fields the term evaluator reads from a backend (row-major, flattened, as the CPU core's).
FIELDS = (
    "qpos",
    "qvel",
    "qpos0",
    "action",
    "ctrl",
    "qfrc_actuator",
    "qfrc_constraint",
    "cfrc_ext",
    "cfrc_int",
    "cacc",
    "cinert",
    "cvel",
    "xpos",
    "xipos",
    "site_xpos",
    "ten_length",
    "ten_velocity",
    "mass_center",
    "actuator_force",
)

TERM_KINDS = ("velocity", "healthy", "sum_squares", "norm", "quadratic", "value", "constant")
INFO_KINDS = ("value", "norm", "velocity", "term")
HEALTH_KINDS = ("finite", "in_range", "fails_if")
RESET_DISTS = ("uniform", "normal", "constant")


class Unsupported(SpecError):
    """A spec with parts the GPU executor cannot run (code E1700); ``parts`` lists them all."""

    def __init__(self, spec_id: str, backend: str, parts: list[str]) -> None:
        self.code = CODE
        self.parts = list(parts)
        lines = "\n".join(f"  - {p}" for p in parts)
        super().__init__(
            f"error[{CODE}]: the `{backend}` GPU executor cannot run {len(parts)} part(s) of "
            f"`{spec_id}`; nothing is dropped silently, so it refuses the spec:\n{lines}\n"
            f"  = help: run it on the CPU core (`envc.make_vec(..., backend=None)`), or switch "
            f"these parts off with their `when` parameters"
        )


@dataclass(frozen=True)
class Plan:
    """One task spec, resolved: the JSON of `gpu_plan` with the compiled model's MJB bytes."""

    raw: dict[str, Any]
    mjb: bytes

    @property
    def id(self) -> str:
        spec_id: str = self.raw["id"]
        return spec_id

    def __getitem__(self, k: str) -> Any:
        return self.raw[k]

    def sources(self) -> Iterator[tuple[str, dict[str, Any]]]:
        """Every selection the env reads (observation, terms, health, info), with its place."""
        for s in self.raw["observation"]:
            yield f"[observation.{s['name']}]", s["source"]
            if s["minus"]:
                yield f"[observation.{s['name']}]", s["minus"]
        for t in self.raw["reward"]:
            for k in ("source", "minus"):
                if t.get(k):
                    yield f"[reward.{t['name']}]", t[k]
        for h in self.raw["health"]:
            for s in h["sources"]:
                yield f"[health.{h['name']}]", s
        for i in self.raw["info"]:
            for k in ("source", "minus"):
                if i.get(k):
                    yield f"[info.{i['key']}]", i[k]

    def fields(self) -> set[str]:
        out = {s["field"] for _, s in self.sources()}
        out |= {r["target"]["field"] for r in self.raw["reset"]}
        return out

    def refusals(self, backend_fields: Collection[str] = FIELDS) -> list[str]:
        """Every part of the spec this executor cannot run, in spec order (empty: runs all)."""
        out = list(self.raw["not_exported"])
        for t in self.raw["reward"]:
            if t["kind"] not in TERM_KINDS:
                out.append(f"[reward.{t['name']}] kind = \"{t['kind']}\"")
        for h in self.raw["health"]:
            if h["kind"] not in HEALTH_KINDS:
                out.append(f"[health.{h['name']}] kind = \"{h['kind']}\"")
        for i in self.raw["info"]:
            if i["kind"] not in INFO_KINDS and f"[info.{i['key']}]" not in " ".join(out):
                out.append(f"[info.{i['key']}] kind = \"{i['kind']}\"")
        for r in self.raw["reset"]:
            if r["dist"]["kind"] not in RESET_DISTS:
                out.append(f"[reset.{r['name']}] kind = \"{r['dist']['kind']}\"")
        seen = set()
        for where, s in self.sources():
            if s["field"] not in backend_fields and (where, s["field"]) not in seen:
                seen.add((where, s["field"]))
                out.append(f"{where} reads `{s['text']}` (field `{s['field']}`)")
        return list(dict.fromkeys(out))


def load(id_or_path: str, overrides: list[tuple[str, str]]) -> Plan:
    from .. import _envc

    text, mjb = _envc.gpu_plan(id_or_path, overrides)
    return Plan(json.loads(text, object_hook=_nonfinite), bytes(mjb))


def _nonfinite(obj: dict[str, Any]) -> float | dict[str, Any]:
    # ±inf and NaN travel as {"f64": "inf"} (JSON has no such numbers).
    if len(obj) == 1 and "f64" in obj:
        return float(obj["f64"])
    return obj
