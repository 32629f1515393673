"""What the term checks against published formulas share (joystick_terms.py, mjlab_terms.py): a
site's velocity from the dumped mjData arrays as MuJoCo defines it, and the comparison with its
tolerance (1e-12 relative unless given, 1e-15 absolute near zero)."""

import numpy as np


def site_vel(m, r, s, local):
    """mj_objectVelocity(site): (angular, linear) at site `s` of row `r`, world or site frame."""
    cvel = np.array(r["cvel"]).reshape(-1, 6)
    com = np.array(r["subtree_com"]).reshape(-1, 3)
    pos = np.array(r["site_xpos"]).reshape(-1, 3)[s]
    b = m.site_bodyid[s]
    ang, lin = cvel[b, :3], cvel[b, 3:]
    lin = lin - np.cross(pos - com[m.body_rootid[b]], ang)
    if local:
        R = np.array(r["site_xmat"]).reshape(-1, 3, 3)[s]
        return R.T @ ang, R.T @ lin
    return ang, lin


class Close:
    """`close(name, envc, numpy, t)`: within tolerance (else printed, False); `worst` is the
    largest relative difference seen."""

    def __init__(self, label, rtol=1e-12):
        self.label, self.worst, self.rtol = label, 0.0, rtol

    def __call__(self, name, got, want, t):
        got, want = np.asarray(got, float), np.asarray(want, float)
        rel = np.abs(got - want) / np.maximum(np.abs(want), 1e-300)
        self.worst = max(self.worst, float(np.max(np.where(got == want, 0.0, rel))))
        if not np.allclose(got, want, rtol=self.rtol, atol=1e-15):
            print(f"{self.label} {t}: {name}: envc {got} numpy {want}")
            return False
        return True
