"""The G-function table of seed 002 (L1323-L1522) as data.

Each known G function has a modal group (``None`` when it acts only in its
block), what happens to it at M02/M30/reset (``reset="default"`` restores the
group's power-on default, ``"keep"`` survives — the manual's ``!`` flag), and
its support status in fagorcnc.  Power-on defaults that depend on a machine
parameter are functions of the :class:`~fagorcnc.config.machine.Machine`.

The interpreter consults only this table to know the groups, to restore the
defaults and to report functions it cannot honour; no G number is special-
cased elsewhere for those purposes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..config.machine import Machine


@dataclass(frozen=True)
class GFunction:
    number: int
    group: str | None
    reset: str          # "default" | "keep" | "block" (acts in its block only)
    meaning: str
    seed: str
    support: str = "yes"  # "yes" | "recorded" (state kept for later stages) | "no"


#: group -> power-on default as a function of the machine (None: no default member)
GROUP_DEFAULTS: dict[str, Callable[[Machine], int | None]] = {
    "motion": lambda m: 1 if m.default("IMOVE") else 0,           # L6022-L6028
    "plane": lambda m: 18 if m.default("IPLANE") else 17,         # L2991-L2996
    "units": lambda m: 70 if m.default("INCHES") else 71,         # L2430-L2436
    "distance": lambda m: 91 if m.default("ISYSTEM") else 90,     # L2478-L2484
    "feed": lambda m: 95 if m.default("IFEED") else 94,           # L4178-L4184
    "corner": lambda m: (50, 5, 7)[m.default("ICORNER")],         # L8103-L8110
    "transition": lambda m: 137 if m.default("IRCOMP") else 136,  # L9585-L9591
    "compensation": lambda m: 40,                                 # L9461-L9465
    "comp_start": lambda m: 139,                                  # L9645-L9650
    "diameter": lambda m: 151 if any(a.diameter for a in m.axes.values()) else 152,  # L2606-L2616
    "css": lambda m: 97,                                          # L5451-L5458
    "feed_point": lambda m: 197,                                  # L4314-L4319
    "accel": lambda m: None,                                      # 100 % (L4445)
    "jerk": lambda m: None,                                       # 100 % (L4493)
    "hirth": lambda m: 171,                                       # L9289-L9293
    "arc_centre": lambda m: 262,                                  # L6941-L6946
    "centre_correction": lambda m: 265,                           # L7013-L7018
    "manual_intervention": lambda m: 202,                         # L7728-L7729
    "origin": lambda m: None,                                     # kept (L3547-L3553)
    "cycle": lambda m: 80,                                        # no canned cycle (09 §1.1, L1449)
    "cycle_return": lambda m: 98,                                 # G98 (09 §1.1 [UNVERIFIED])
}


def _g(number, group, reset, meaning, seed, support="yes"):
    return GFunction(number, group, reset, meaning, seed, support)


_TABLE = [
    _g(0, "motion", "default", "rapid positioning", "L6022"),
    _g(1, "motion", "default", "linear interpolation", "L6106"),
    _g(2, "motion", "default", "clockwise arc", "L6328"),
    _g(3, "motion", "default", "counter-clockwise arc", "L6328"),
    _g(4, None, "block", "dwell", "L9174"),
    _g(5, "corner", "default", "controlled corner rounding", "L8103", "recorded"),
    _g(6, None, "block", "arc centre in absolute coordinates", "L6931"),
    _g(7, "corner", "default", "square corner", "L8014", "recorded"),
    _g(8, None, "block", "arc tangent to the previous path", "L7077"),
    _g(9, None, "block", "arc through three points", "L7181"),
    # mirror images cumulate (G11-G13) and reset per MIRRORCANCEL: kept as state, not as one group
    _g(10, None, "keep", "mirror image cancel", "L8779"),
    _g(11, None, "keep", "mirror image on X", "L8781"),
    _g(12, None, "keep", "mirror image on Y", "L8781"),
    _g(13, None, "keep", "mirror image on Z", "L8781"),
    _g(14, None, "keep", "mirror image in programmed directions", "L8781"),
    _g(17, "plane", "default", "plane XY, longitudinal Z", "L2991"),
    _g(18, "plane", "default", "plane ZX, longitudinal Y", "L2991"),
    _g(19, "plane", "default", "plane YZ, longitudinal X", "L2991"),
    _g(20, "plane", "default", "plane from two directions", "L3117"),
    _g(30, None, "block", "polar origin preset", "L3994"),
    _g(31, None, "block", "temporary polar origin at the arc centre", "L6903"),
    _g(33, "motion", "default", "electronic threading", "L7285"),
    _g(36, None, "block", "corner rounding", "L8471"),
    _g(37, None, "block", "tangential entry", "L8650"),
    _g(38, None, "block", "tangential exit", "L8696"),
    _g(39, None, "block", "chamfer", "L8581"),
    _g(40, "compensation", "default", "cancel radius compensation", "L9461"),
    _g(41, "compensation", "default", "radius compensation left", "L9461"),
    _g(42, "compensation", "default", "radius compensation right", "L9461"),
    _g(45, None, "block", "tangential control", "L12059"),
    _g(50, "corner", "default", "semi-rounded corner", "L8055", "recorded"),
    _g(53, "origin", "keep", "cancel origin offset", "L3897"),
    *[_g(n, "origin", "keep", f"absolute zero offset {n - 53}", "L3547") for n in range(54, 60)],
    _g(60, None, "block", "square corner (this block)", "L8018", "recorded"),
    _g(61, None, "block", "controlled rounding (this block)", "L8107", "recorded"),
    _g(63, "motion", "default", "rigid tapping", "L7555"),
    _g(70, "units", "default", "inches", "L2430"),
    _g(71, "units", "default", "millimetres", "L2430"),
    _g(72, None, "keep", "scale factor", "L8989"),
    _g(73, None, "default", "coordinate system rotation", "L8946"),
    _g(74, None, "block", "home search", "L2357"),
    _g(90, "distance", "default", "absolute coordinates", "L2478"),
    _g(91, "distance", "default", "incremental coordinates", "L2478"),
    _g(92, "origin", "keep", "coordinate preset", "L3418"),
    _g(93, "feed", "default", "feed as time in seconds", "L4178"),
    _g(94, "feed", "default", "feed per minute", "L4178"),
    _g(95, "feed", "default", "feed per revolution", "L4178"),
    _g(96, "css", "keep", "constant surface speed", "L5451", "recorded"),
    _g(97, "css", "keep", "constant spindle speed", "L5451"),
    _g(108, None, "block", "feed adaptation at block start", "L4256", "recorded"),
    _g(109, None, "block", "feed adaptation at block end", "L4256", "recorded"),
    _g(112, None, "keep", "axis parameter set", "L9339"),
    _g(130, "accel", "default", "acceleration % per axis", "L4445", "recorded"),
    _g(131, "accel", "default", "acceleration % global", "L4445", "recorded"),
    _g(132, "jerk", "default", "jerk % per axis", "L4493", "recorded"),
    _g(133, "jerk", "default", "jerk % global", "L4493", "recorded"),
    _g(134, None, "default", "feed-forward %", "L4544", "recorded"),
    _g(135, None, "default", "AC-forward %", "L4600", "recorded"),
    _g(136, "transition", "default", "circular transition (compensation)", "L9585", "recorded"),
    _g(137, "transition", "default", "linear transition (compensation)", "L9585", "recorded"),
    _g(138, "comp_start", "default", "direct compensation start", "L9645", "recorded"),
    _g(139, "comp_start", "default", "indirect compensation start", "L9645", "recorded"),
    _g(145, None, "block", "suspend tangential control", "L12236"),
    _g(151, "diameter", "default", "diameter programming", "L2606"),
    _g(152, "diameter", "default", "radius programming", "L2606"),
    _g(157, None, "block", "exclude axes from the next zero offset", "L3866"),
    _g(158, None, "keep", "incremental zero offset", "L3776"),
    _g(159, "origin", "keep", "zero offset n (G159=n)", "L3470"),
    _g(170, "hirth", "default", "deactivate Hirth axes", "L9289", "recorded"),
    _g(171, "hirth", "default", "activate Hirth axes", "L9289", "recorded"),
    _g(174, None, "keep", "set machine coordinate", "L3313"),
    _g(192, None, "keep", "spindle speed limit", "L5394", "recorded"),
    _g(193, None, "block", "feed interpolation", "L4258", "recorded"),
    _g(196, "feed_point", "default", "constant feed at the cutting point", "L4314"),
    _g(197, "feed_point", "default", "constant feed at the tool centre", "L4314"),
    _g(198, None, "keep", "lower software limits", "L9233"),
    _g(199, None, "keep", "upper software limits", "L9233"),
    _g(200, None, "block", "exclusive manual intervention", "L7724"),
    _g(201, "manual_intervention", "default", "additive manual intervention on", "L7724"),
    _g(202, "manual_intervention", "default", "additive manual intervention off", "L7728"),
    _g(261, "arc_centre", "default", "arc centre absolute (modal)", "L6941"),
    _g(262, "arc_centre", "default", "arc centre relative to the start", "L6941"),
    _g(263, None, "keep", "arc radius programming", "L6418"),
    _g(264, "centre_correction", "default", "cancel arc-centre correction", "L7013", "recorded"),
    _g(265, "centre_correction", "default", "activate arc-centre correction", "L7013", "recorded"),
    _g(266, None, "block", "feed override forced to 100 %", "L4371", "recorded"),
    # canned cycles of the milling model (L1447-L1487; parameters: spec 09, fagorcnc/interp/cycles);
    # G80 also cancels a modal subroutine (L10798, L11033)
    _g(80, "cycle", "default", "cancel the canned cycle (and the modal subroutine)", "L1449"),
    _g(81, "cycle", "default", "drilling canned cycle", "L1451"),
    _g(82, "cycle", "default", "deep-hole drilling, variable peck", "L1453"),
    _g(83, "cycle", "default", "deep-hole drilling, constant peck", "L1455"),
    _g(84, "cycle", "default", "tapping canned cycle", "L1457"),
    _g(85, "cycle", "default", "reaming canned cycle", "L1459"),
    _g(86, "cycle", "default", "boring canned cycle", "L1461"),
    _g(87, "cycle", "default", "rectangular pocket canned cycle", "L1463"),
    _g(88, "cycle", "default", "circular pocket canned cycle", "L1465"),
    _g(98, "cycle_return", "default", "canned cycle: return to the starting plane", "L1467"),
    _g(99, "cycle_return", "default", "canned cycle: return to the reference plane", "L1469"),
    *[_g(n, None, "block", f"multiple machining {what}", f"L{1471 + 2 * (n - 160)}")
      for n, what in ((160, "in a line"), (161, "in a parallelogram"), (162, "in a grid"), (163, "in a circle"),
                      (164, "in an arc"), (165, "by a chord"))],
    _g(210, "cycle", "default", "bore milling canned cycle", "L1483"),
    _g(211, "cycle", "default", "inside thread milling canned cycle", "L1485"),
    _g(212, "cycle", "default", "outside thread milling canned cycle", "L1487"),
]
# Probing and the lathe-model cycles are described in other manuals (seed 002 L1433-L1522).
_OTHER_MANUAL = {89, 100, 101, 102, 103, 104, 66, 68, 69}

G_FUNCTIONS: dict[int, GFunction] = {g.number: g for g in _TABLE}
for _n in _OTHER_MANUAL:
    G_FUNCTIONS[_n] = GFunction(_n, None, "block", "canned cycle or probing (another manual)", "L1433", "no")
for _n in (*range(180, 190), *range(380, 400)):
    G_FUNCTIONS[_n] = GFunction(_n, None, "block", "OEM subroutine call", "L10670")
for _n in range(500, 600):
    G_FUNCTIONS[_n] = GFunction(_n, None, "block", "user generic subroutine call", "L10961")

#: Groups whose members are mutually exclusive in one block (spec 01 §5.7, E17).
EXCLUSIVE_GROUPS = frozenset(GROUP_DEFAULTS)


def power_on_modes(machine: Machine) -> dict[str, int | None]:
    """The modal state at power-on: group -> active G number."""
    return {group: default(machine) for group, default in GROUP_DEFAULTS.items()}
