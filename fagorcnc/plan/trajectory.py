"""The planned motion sampled at a fixed period (what a servo or step back-end consumes)."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from .independent import IndependentSegment
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
    An axis positioned by #MOVE follows its independent segments over their time
    (:func:`_independent`).
    """
    n_axes = len(axes)
    ts, pos, vel, acc, jrk, lines = [], [], [], [], [], []
    here = np.array([(start or {}).get(a, 0.0) for a in axes], dtype=float)
    k_end = 0
    independent: list[IndependentSegment] = []
    for seg in segments:
        if type(seg) is IndependentSegment:
            independent.append(seg)
            continue
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
    if independent:
        _independent(independent, axes, period, t, arrays)
    return Trajectory(t, *({a: arr[:, i] for i, a in enumerate(axes)} for arr in arrays),
                      line=np.concatenate(lines), period=period)


def _independent(segments: list[IndependentSegment], axes: list[str], period: float, t: np.ndarray,
                 arrays: list[np.ndarray]) -> None:
    """The axes positioned by #MOVE, from their independent segments (plan/independent.py), over the samples
    ``t`` of the general ones.  The axis is the sum of both interpolators (seed 002 L16622-L16623); while it
    runs independently the general interpolator holds it (a general move of it is refused until #SYNC POS,
    which waits for the positioning to end) and the general records already carry it at the target, so over
    the independent segments' time the sum is the independent motion: it replaces the axis's column there
    (held at rest during an in-position wait)."""
    pos, vel, acc, jrk = arrays
    ks = np.rint(t / period).astype(np.int64)
    held: dict[str, float] = {}
    for seg in sorted(segments, key=lambda s: s.t0):
        i = axes.index(seg.axis)
        t0, t1 = seg.t0, seg.t0 + seg.duration
        k0 = int(np.ceil(t0 / period - 1e-9))
        k1 = int(np.ceil(t1 / period - 1e-9))
        lo, hi = np.searchsorted(ks, (k0, k1))
        if seg.kind != "motion":
            if hi > lo and seg.axis in held:
                pos[lo:hi, i] = held[seg.axis]
                vel[lo:hi, i] = acc[lo:hi, i] = jrk[lo:hi, i] = 0.0
            continue
        held[seg.axis] = float(seg.piece.end[i])
        if hi <= lo:
            continue
        if seg.profile is None:
            raise ValueError("sample() needs segments planned with keep_profiles=True")
        s, v, a, j = seg.profile.at(ks[lo:hi] * period - t0)
        q, d1, d2, d3 = seg.piece.derivatives(s)
        q, d1, d2, d3 = q[:, i], d1[:, i], d2[:, i], d3[:, i]
        pos[lo:hi, i] = q
        vel[lo:hi, i] = d1 * v
        acc[lo:hi, i] = d1 * a + d2 * v * v
        jrk[lo:hi, i] = d1 * j + 3.0 * d2 * v * a + d3 * v ** 3
