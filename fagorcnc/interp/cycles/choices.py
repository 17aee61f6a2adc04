"""Every [UNVERIFIED] / [CONSTRUCTION] choice of the canned cycles, in one place.

The 8060/8065 manual (seed 002) names the cycles and gives the influence-zone,
NR and V.C rules; the parameters and move sequences were rebuilt from Fagor's
8055/8060/8070 documentation and from what the Autodesk post writes
(``shared/spec/fagor/09-canned-cycles.md``, "the digest").  Where no source
fixes a rule the digest recommends a choice; each one is a named constant
here, with the digest section it comes from, so it can be changed in one place
when the cycles manual is found.

The [CONSTRUCTION] tool paths are algorithms rather than constants; they live in one function
each: ``pockets._rectangles`` / ``pockets._finish_contour`` (G87, §2.7.1-§2.7.2),
``pockets._circles`` (G88, §2.8), ``milling.ops`` (G210, §2.9), ``threads.ops`` (G211/G212, §2.9),
and the point orders of ``patterns`` (§2.10).  Where spec 09 is silent this implementation chose (and says so here):

* G87 with the pocket taller than long (b > a): the pocket axes are turned by 90 degrees rather
  than swapped, so the machining direction (sign of J) is kept (a swap would mirror it);
* G87 M2 chamfers: the tool centre follows the chamfer offset by r, cutting
  ``Q - r(2 - sqrt 2)`` off each side of the finishing rectangle (none when that is <= 0);
* G87/G88 with a tool of radius 0: C must be programmed; the C <= diameter check needs r > 0;
* G210 with a depth that is not a whole number of pitches B: the last turn is partial and the
  bottom is finished along the circle back to the start angle, so the exit always starts at rho;
* G83 with |I| below the 1 mm approach: the re-approach stops at the reference plane;
* G163/G164 C2/C3 arcs follow the C letter literally (C2 clockwise, C3 counter-clockwise), whatever
  the sign of I;
* G211/G212 (§2.9 gives only the radii and "one helix turn per pitch B between Zr and Zb"):
  J is read as the radius the tooth tip reaches (the thread's root: the major radius inside, the minor
  radius outside -- with a "nominal" major radius the G212 pass at ``|J| + r`` would cut nothing); one
  radial pass (no source gives several); the approach is a rapid from the axis to the clearance radius at
  Zr (C1: then a rapid down to Zb there); the entry semicircle (radius K/2, flat at the start level) is
  tangent to the helix, so it turns with the helix inside (G211) and against it outside (G212); a partial
  last turn ends off the start angle and the exit semicircle leaves from there (no flat finishing circle,
  which would cut a groove across the thread); after the exit G211 goes to the axis and then up, G212 up
  at the clearance radius (to the return level, at least Zr) and then to the axis, so the tool never
  crosses the stud; a right-hand helix turns counter-clockwise (seen from +l) while it rises along +l, so
  a right-hand thread milled top-down turns G02; H has no meaning and is refused; J <= 0 is refused (the
  hand is B's sign);
* V.C writes with no cycle active change the stored values only (read back by V.C.x);
* a #MCALL programmed while a cycle is active is cancelled by the next hole: the seed says a cycle's
  activation cancels #MCALL (L10570) and its execution cancels an OEM modal subroutine (L10807);
  the execution rule is applied to both.
"""

from __future__ import annotations

#: §1.1: G98 (return to the starting plane) is the power-on / reset default of G98/G99.
DEFAULT_RETURN = 98

#: §1.1: a change of work plane (G17/G18/G19/G20) or of the tool axis (#TOOL AX) cancels the cycle.
CANCEL_ON_PLANE_CHANGE = True

#: §1.2: a block of the influence zone that also moves the longitudinal axis is a plain move,
#: without the cycle (a warning says so), rather than an implicit new starting plane.
LONGITUDINAL_MOVE_SKIPS_CYCLE = True

#: §1.2: the absolute levels Zs, Zr, Zb are computed once, at the definition block; a write to
#: V.C.Z / V.C.I recomputes them with the G90/G91 state of the definition.
LEVELS_AT_DEFINITION = True

#: §1.3: Zs between Zr and Zb is not an error: the approach is a rapid from Zs to Zr.
START_BETWEEN_LEVELS_OK = True

#: §1.4 step 1: the positioning in the plane is a rapid, whatever G00/G01 is active.
POSITIONING_RAPID = True

#: §1.4: a hole cycle entered with the spindle stopped is simulated and a warning given.
WARN_SPINDLE_STOPPED = True

#: §1.4: pocket and milling cycles start the spindle clockwise (M03) when it is stopped.
POCKET_STARTS_SPINDLE = 3

#: §1.4: radius compensation G41/G42 active at a cycle is an error (cancel it with G40 first).
RADIUS_COMP_IS_ERROR = True

#: §1.4 [UNVERIFIED]: the PLC mark RIGID (seed 002 L29856: "rigid tapping (G63)") is also on during G84 R1.
RIGID_MARK_IN_G84_R1 = True

#: §1.2: V.G.CYCLETYPEON (PLC and interface only, seed 002 L40300) is the active cycle's G number, 0 when none.
NO_CYCLE_TYPE = 0

#: §2.2 G82: approach clearance C when not programmed (or C0), mm.
G82_APPROACH = 1.0
#: §2.2 G82: minimum peck L when not programmed, mm.
G82_MIN_PECK = 1.0
#: §2.2 G82: J0 (or J absent) means a full retract to Zr after every step, as J1.
G82_J_ZERO = 1

#: §2.3 G83: the re-approach stops this far short of the previous bottom, mm (8055 fixed value).
G83_APPROACH = 1.0

#: §2.4 G84 rigid tapping with pecks B: after each peck the tap goes back to the reference plane.
G84_PECK_RETURN_TO_ZR = True
#: §2.4 G84: entering a tapping cycle with the spindle stopped is an error.
G84_SPINDLE_STOPPED_IS_ERROR = True

#: §2.7 G87/G88: at the end of each level the tool lifts this far off the floor (towards Zr), mm.
POCKET_LIFT = 1.0
#: §2.7 G87/G88: side step C when not programmed (or C0), as a share of the tool diameter (8060 p71).
POCKET_STEP_OF_DIAMETER = 0.75
#: §2.7 G87/G88: plunge feed V when not programmed (or V0), as a share of F.
POCKET_PLUNGE_OF_F = 0.5

#: §2.9: G210 semantics are provisional (no source gives its parameters); a warning says so each time.
G210_PROVISIONAL = True
#: §2.9: G211/G212 semantics are provisional too (recommended meanings of the digest, path
#: [CONSTRUCTION]); warning CYC020 at each definition.
THREAD_PROVISIONAL = True
#: §2.9: the sign of B that means a right-hand thread (B+ right-hand, B- left-hand).
THREAD_RIGHT_HAND_B = 1

#: §2.10: G160-G162 move between points in rapid.
PATTERN_LINE_RAPID = True
#: §2.10: skip syntax Pn.m: m is written with 3 decimals (P5.008 skips points 5 to 8).
SKIP_RANGE_DECIMALS = 3
#: §2.10: derived counts (K = X/I + 1 ...) must be whole within this tolerance.
PATTERN_WHOLE_TOLERANCE = 1e-6
