"""The planned motion sampled at a fixed period (what a servo or step back-end consumes)."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from .planner import Segment


@dataclass
class Trajectory:
    """Samples at ``t`` (s): per-axis position (mm, deg), velocity (/s),
    acceleration (/s²) and jerk (/s³) in machine coordinates, and the source
    line of each sample."""

    t: np.ndarray
    position: dict[str, np.ndarray]
    velocity: dict[str, np.ndarray]
    acceleration: dict[str, np.ndarray]
    jerk: dict[str, np.ndarray]
    line: np.ndarray
    period: float

    def __len__(self) -> int:
        return len(self.t)


def sample(segments: Iterable[Segment], axes: list[str], period: float = 0.001,
           start: dict | None = None) -> Trajectory:
    """Sample planned segments (planned with ``keep_profiles=True``) every ``period`` seconds.

    Samples fall at ``k * period`` from the start of the motion; the last one
    is the first grid time at or after the end, at rest at the final position.
    """
    n_axes = len(axes)
    ts, pos, vel, acc, jrk, lines = [], [], [], [], [], []
    here = np.array([(start or {}).get(a, 0.0) for a in axes], dtype=float)
    k_end = 0
    for seg in segments:
        t0, t1 = seg.t0, seg.t0 + seg.duration
        k0 = int(np.ceil(t0 / period - 1e-9))
        k1 = int(np.ceil(t1 / period - 1e-9))
        k_end = max(k_end, k1)
        if seg.kind != "motion":
            if k1 > k0:
                n = k1 - k0
                ts.append(np.arange(k0, k1) * period)
                pos.append(np.broadcast_to(here, (n, n_axes)))
                zero = np.zeros((n, n_axes))
                vel.append(zero)
                acc.append(zero)
                jrk.append(zero)
                lines.append(np.full(n, seg.line))
            continue
        if seg.profile is None:
            raise ValueError("sample() needs segments planned with keep_profiles=True")
        if k1 > k0:
            t = np.arange(k0, k1) * period
            # times inside the segment as small exact steps plus one offset: no rounding noise
            # from large absolute times between neighbouring samples
            s, v, a, j = seg.profile.at(np.arange(k1 - k0) * period + (k0 * period - t0))
            q, d1, d2, d3 = seg.piece.derivatives(s)
            v, a, j = v[:, None], a[:, None], j[:, None]
            ts.append(t)
            pos.append(q)
            vel.append(d1 * v)
            acc.append(d1 * a + d2 * v * v)
            jrk.append(d1 * j + 3.0 * d2 * v * a + d3 * v ** 3)
            lines.append(np.full(len(t), seg.line))
        here = seg.piece.end
    # the end point, at rest
    ts.append(np.array([k_end * period]))
    pos.append(here[None, :])
    zero = np.zeros((1, n_axes))
    vel.append(zero)
    acc.append(zero)
    jrk.append(zero)
    lines.append(np.array([lines[-1][-1] if lines else 0]))
    t = np.concatenate(ts)
    arrays = [np.concatenate(x) for x in (pos, vel, acc, jrk)]
    return Trajectory(t, *({a: arr[:, i] for i, a in enumerate(axes)} for arr in arrays),
                      line=np.concatenate(lines), period=period)
