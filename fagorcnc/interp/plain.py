"""The fast path of the commonest CAM block: a plain move of literal words.

Most blocks of a CAM program are ``N1230 G1 X12.5 Y-3.25 Z-1 F800`` or ``G2 X.. Y.. I.. J..``:
an optional block number, a motion G function (G00-G03) and G90/G91, axis words, the arc's
I J K or R and a feed, all literal numbers.  For such a block the general executor
(:meth:`~fagorcnc.interp.words.WordsMixin.classify` then :meth:`~fagorcnc.interp.iso.IsoExecutor.execute`)
walks some sixty checks of functions the block does not hold (origins, spindles, tools, M and H
functions, cycles, transformations ...), each of which does nothing.  :class:`PlainBlocks`
recognises the block from its words and the few modal conditions that would make those checks
do something, and runs only what the general path would have run: the same modal changes, the
same feed (:meth:`~fagorcnc.interp.iso.IsoExecutor._feed`), the same motion
(:meth:`~fagorcnc.interp.motion.MotionMixin._motion`, shared with the general path) and the same
lint.  Records, diagnostics and errors are the general path's; anything else (an expression, a
parameter, another G function, a word written twice, an active canned cycle, #MCALL, #MCS, a
coupled or parked axis ...) returns :data:`NOT_PLAIN` before anything changed, and the block goes
the general way.  A G00/G01 of axis words without transformation, radius compensation or kinematics
is made by :meth:`PlainBlocks._line`, ``_motion``'s steps for that case in the same order and with
the same arithmetic, and a G02/G03 by its centre or its radius (helix included) by
:meth:`PlainBlocks._arc`, ``_motion`` then ``_arc``'s steps; their records by :func:`record_maker` (no
dataclass ``__init__``).
``tests/test_plain_blocks.py`` runs programs both ways and compares everything.
"""

from __future__ import annotations

import dataclasses
import math

from ..path import arcs
from ..syntax.ast import Block, PlainWords, Word
from . import compat
from .expressions import InterpError
from .records import _FEED_MODES, _JOINS, Arc, Line, Source, feed_mode, shared_tuple
from .units import INCH
from .words import BlockWords

#: What :meth:`PlainBlocks.run` returns for a block it does not take: the general executor runs it.
NOT_PLAIN = object()

#: G functions a plain block may hold: their number and modal group (``gtable.G_FUNCTIONS``).
_PLAIN_G = {0.0: (0, "motion"), 1.0: (1, "motion"), 2.0: (2, "motion"), 3.0: (3, "motion"),
            90.0: (90, "distance"), 91.0: (91, "distance")}
#: The largest block number (``Evaluator.integer``'s range for N).
_MAX_N = 4294967295.0
#: The centre letters of each plane (abscissa, ordinate) and the helix pitch letter (``motion._CENTRE_LETTERS``).
_CENTRE_LETTERS = {17: ("I", "J", "K"), 18: ("K", "I", "J"), 19: ("J", "K", "I")}
#: Feed modes whose moves are not checked against a stopped spindle (as ``IsoExecutor.execute``).
_NO_SPINDLE_LINT = ("G95", "G33", "G63")


_G, _N, _F, _PARAM = 1, 2, 3, 4   # roles of the letters that are not axes


def _roles(by_name: dict, configured) -> dict:
    """What each address of a plain block is, as ``WordsMixin._classify`` tests them in turn: G, N and F
    first, then the channel's axes (program name -> machine axis), then I J K R when no configured axis
    has that name (an axis of the machine outside the channel is an error of the general path)."""
    roles: dict = {}
    for letter in "IJKR":
        if letter not in configured and letter not in by_name:
            roles[letter] = _PARAM
    roles.update(by_name)
    roles.update({"G": _G, "N": _N, "F": _F})
    return roles


class PlainBlocks:
    """Runs plain blocks for an :class:`~fagorcnc.interp.interpreter.Interpreter` (see the module)."""

    __slots__ = ("_cirinerr", "_cirinfact", "_diameter", "_linear", "_max_feed", "_names", "_roles", "interp", "iso",
                 "seconds", "state")

    def __init__(self, interp) -> None:
        self.interp = interp
        self.iso = interp.iso
        self.state = interp.state
        self._names: dict | None = None   # the channel's by_name the roles were made for
        self._roles: dict = {}
        axes = interp.state.machine.axes   # the machine's configuration does not change during a run
        self._linear = frozenset(a for a, ax in axes.items() if not ax.rotary)
        self._diameter = frozenset(a for a, ax in axes.items() if ax.diameter)
        self._max_feed = interp.machine.max_feed   # MAXFEED (_active_feed's clamp)
        self._cirinerr, self._cirinfact = interp.machine.cirinerr, interp.machine.cirinfact   # _radius_check's
        #: record_time() of the last record :meth:`run` made, when it worked it out on the way (a G01), else None
        self.seconds: float | None = None

    def run(self, block: Block):
        """The record of ``block`` (None when it moves nothing, as ``F800`` alone), or :data:`NOT_PLAIN`
        when it is not a plain block.  Raises the general path's :class:`InterpError` where it would."""
        self.seconds = None
        st = self.state
        interp = self.interp
        channel = st.channel
        if interp.modal_call is not None or st.mcs_on or st.cycles.active is not None or channel.links \
                or channel.parked or interp.curves.independent:
            # #MCALL after the move, #MCS, a canned cycle, coupled or parked axes, an axis a #MOVE moved
            # before #SYNC POS (MotionMixin._motion refuses a general move of it: INT232)
            return NOT_PLAIN
        by_name = channel.by_name
        if self._names is not by_name:   # the channel's axes changed (#SET AX, #RENAME AX ...): roles again
            self._names, self._roles = by_name, _roles(by_name, st.machine.axes)
        roles = self._roles
        axes: dict = {}
        params: dict = {}
        gl: list = []
        groups = 0   # bit 1: a motion G, bit 2: a G90/G91 (two of one group: the general path says)
        motion = None
        feed = None
        number = None
        items = block.items
        if type(items) is not PlainWords and not _literal_words(items):
            return NOT_PLAIN
        for addr, value, col, _eq in items:
            role = roles.get(addr)
            if type(role) is str:   # an axis of the channel: its machine axis
                if role in axes:
                    return NOT_PLAIN   # INT023
                axes[role] = (value, col)
            elif role is _G:
                g = _PLAIN_G.get(value)
                if g is None:
                    return NOT_PLAIN
                bit = 1 if g[1] == "motion" else 2
                if groups & bit:
                    return NOT_PLAIN   # INT012, or a repeated G function
                groups |= bit
                if bit == 1:
                    motion = g[0]
                gl.append((g, col))
            elif role is _PARAM:
                if addr in params:
                    return NOT_PLAIN   # INT023
                params[addr] = (value, col)
            elif role is _F:
                feed = (value, col)   # the last F counts, as in classify()
            elif role is _N:
                if not (0.0 <= value <= _MAX_N and value.is_integer()):
                    return NOT_PLAIN   # INT036, INT037
                number = value
            else:
                return NOT_PLAIN
        modes = st.modes
        if (modes["motion"] if motion is None else motion) not in (0, 1, 2, 3):
            return NOT_PLAIN   # G33, G63 ... active: the general path
        # from here on, what IsoExecutor.classify() and execute() do for these words, in their order
        st.line = block.line
        interp.mcs_block = False
        interp.axis_sentence = None
        if number is not None:
            st.last_n = int(number)
        if groups & 2:   # a G90/G91, the one G function of a plain block from G10 up
            text = block.text
            for (n, _group), col in gl:
                if n >= 10:
                    compat.leading_zero(interp, n, col, text)   # "G090" is G90
        iso = self.iso
        iso.sync.previous_motion = modes["motion"]   # G33 joins the thread of the block before (L7366)
        if motion is not None:
            modes["motion"] = motion
        if groups & 2:
            for (n, group), _col in gl:
                modes[group] = n
        if st.block_modes:
            st.block_modes = {}
        if feed is not None:
            value = feed[0]
            if value > 0 and modes["feed"] != 93:   # IsoExecutor._feed() of a positive F in mm/min or mm/rev
                st.feed_programmed = value
                st.feed = value * INCH if modes["units"] == 70 else value
            else:
                iso._feed(*feed)
        mode = modes["motion"]
        src = _source(interp.frames[-1].program.file, block.line, block.text)   # interp._src(block)
        rec = NOT_PLAIN
        if params if mode >= 2 else axes and not params:
            kin = st.kin
            tr = st.transform
            # the simplest state: no transformation, radius compensation, kinematics or per-block planning
            # context; then _move is MotionMixin._motion's steps for the block
            if (tr.scale == 1.0 and not tr.mirror and tr.angle == 0.0 and modes["compensation"] not in (41, 42)
                    and kin.frame is None and not kin.raw and not kin.pending_ori and not kin.angax
                    and not kin.tangential and not kin.c_axes and not kin.as_linear and not st.block_modes):
                rec = self._move(mode, axes, params, src)
        if rec is NOT_PLAIN:   # the words as classify() sorts them, for _motion
            bw = BlockWords()
            bw.g = [(n, col, None) for (n, _group), col in gl]
            bw.axes = axes
            bw.params = params
            bw.feed = feed
            rec = iso._motion({n: (col, None) for (n, _group), col in gl}, bw, src)
        if rec is not None and st.spindle_state and st.tool and rec.kind != "rapid" \
                and rec.feed_mode not in _NO_SPINDLE_LINT:   # spindle_lint() looks no further without them
            compat.spindle_lint(interp, rec, 1)
        return rec

    # ------------------------------------------------------------ G00-G03 in the simplest state
    def _move(self, mode: int, words: dict, params: dict, src: Source):
        """``MotionMixin._motion`` of a G00-G03 in the simplest state (no transformation, radius compensation,
        kinematics or per-block planning context: :meth:`run`), step by step (the same arithmetic in the same
        order): what a line and an arc share (the plane, the start point, the target), then :meth:`_line` or
        :meth:`_arc`.  The programmed point is the part point (no transformation).  :data:`NOT_PLAIN` before
        anything changed for a rotary axis word (``_motion`` itself: unrolled positions, directions,
        ``IsoExecutor._rotary``) and for an arc this path does not take: another plane than G17-G19, R without
        an end point in the plane (a polar move), neither centre nor R (the stored radius, a null move), a
        letter that is not the plane's."""
        if not self._linear.issuperset(words):
            return NOT_PLAIN
        st = self.state
        modes = st.modes
        plane = modes["plane"]
        letters = None
        if mode >= 2:
            letters = _CENTRE_LETTERS.get(plane)
            if letters is None:
                return NOT_PLAIN   # G20: the general path
        slots = st.channel.slots
        if plane == 17 and len(slots) >= 3:   # plane_axes() of G17, inline
            a, o, n = slots[0], slots[1], slots[2]
        else:
            a, o, n = st.plane_axes()
        by_centre = False
        if letters is not None:
            if a is None or o is None:
                return NOT_PLAIN   # INT150: the general path says it
            ci, cj, ck = letters
            by_centre = ci in params or cj in params
            in_plane = a in words or o in words
            for letter in params:
                if letter != ci and letter != cj and letter != ck and (letter != "R" or by_centre or not in_plane):
                    return NOT_PLAIN   # R with a centre, a polar R, a letter of another plane
            if not by_centre and "R" not in params:
                return NOT_PLAIN   # only the pitch: the stored radius R1=, or none (INT061)
        # programmed_pos() (no transformation: the part position), move_start()
        pos = st.machine_pos
        off, cur_part = _part_point(st, pos)
        last = st._last_end   # move_start(): the last end point when the tool is still there
        start = last if last is not None and last == pos and tuple(last) == tuple(pos) else dict(pos)
        inch = modes["units"] == 70
        incremental = modes["distance"] == 91
        diameter = modes["diameter"] == 151
        end_part = dict(cur_part)   # target(); transform.apply() under no transformation is the same point
        for axis, (v, _col) in words.items():
            if inch:
                v *= INCH
            if diameter and axis in self._diameter:
                v /= 2.0
            end_part[axis] = cur_part[axis] + v if incremental else v
        if letters is None:
            return self._line(mode, words, src, a, o, off, cur_part, start, end_part)
        return self._arc(mode, words, params, src, (a, o, n), letters, by_centre, off, cur_part, start, end_part)

    def _line(self, mode: int, words: dict, src: Source, a: str | None, o: str | None, off: dict | None,
              cur_part: dict, start: dict, end_part: dict):
        """The rest of :meth:`_move` for a G00/G01 from its plane axes ``a`` ``o``, offsets ``off``
        (:func:`_part_point`), part and machine start points and target: the origin chain is worked out again
        only when the tool length compensation changed it."""
        st = self.state
        iso = self.iso
        applied = st.length_offset
        if applied or (st.offset and st.tool):   # _length_compensation() returns at once otherwise
            iso._length_compensation(_Words(words))   # a move of the tool axis applies the tool length (L10072)
            if st.length_offset is not applied:
                off = st.offsets()
        end = _machine_end(st, end_part, off)
        lower, upper = st.lower_limits, st.upper_limits
        for x, v in end.items():   # check_limits() says more only for a point outside the limits
            if not lower[x] - 1e-9 <= v <= upper[x] + 1e-9:
                iso.interp.check_limits(end, next(iter(words.values()))[1], start)
                break
        st.machine_pos = dict(end)   # moved_to()
        st._last_end = end
        if a is not None and o is not None:   # arcs.end_tangent() of a line, inline
            sa, so, ea, eo = cur_part[a], cur_part[o], end_part[a], end_part[o]
            d = math.dist((sa, so), (ea, eo))
            if not d < 1e-12:
                st.tangent = ((ea - sa) / d, (eo - so) / d)
        modes = st.modes
        if mode == 0:   # _compensation() is None, _joins(None) the modal pair
            # Line's fields in order: kind, start, end, end_part, feed, feed_mode, src, comp, dyn, frame, joins
            return _line_record("rapid", start, end, end_part, None, "G94", src, None, st.dynamics(), None,
                                shared_tuple((modes["transition"], modes["comp_start"])))
        # sum(), as Line.length sums (a loop of += would differ in the last bit from Python 3.12 on, whose
        # sum() of floats is compensated); of a list made by a loop: the same sum, in order, without the
        # comprehension's function and closure
        squares = []
        for x, v in end.items():
            squares.append((v - start[x]) ** 2)
        length = math.sqrt(sum(squares))
        mode_f = modes["feed"]
        feed = st.feed
        if mode_f == 94 and feed:   # _active_feed() of G94 with a feed: F itself, at most MAXFEED
            max_feed = self._max_feed
            if max_feed > 0:
                feed = min(feed, max_feed)
        else:
            feed = iso._active_feed(length, start)   # INT060 before anything else is asked, as in _motion
        css = iso._css() if mode_f == 95 else None   # _css() is None outside G95
        if css is None:   # record_time() of the record: the same length (Line.length), the same division
            self.seconds = 0.0 if length == 0.0 else length / feed * 60.0 if feed else 0.0
        dyn = st._dynamics   # st.dynamics(): no per-block modes in the simplest state
        # Line's fields in order: kind, start, end, end_part, feed, feed_mode, src, comp, dyn, frame, joins,
        # thread, css
        return _line_record("linear", start, end, end_part, feed, _FEED_MODES.get(mode_f) or feed_mode(mode_f), src,
                            None, dyn if dyn is not None else st.dynamics(), None,
                            _JOINS.setdefault(joins := (modes["transition"], modes["comp_start"]), joins), None, css)

    def _arc(self, mode: int, words: dict, params: dict, src: Source, plane: tuple, letters: tuple,
             by_centre: bool, off: dict | None, cur_part: dict, start: dict, end_part: dict):
        """The rest of :meth:`_move` for a G02/G03 (then ``MotionMixin._arc``'s steps, seed 002 ch. 8.3-8.5) by
        its centre (the plane's centre ``letters``, from the start point or absolute under G261) or by R,
        helix pitch included, from its plane axes, offsets, part and machine start points and target."""
        st = self.state
        iso = self.iso
        modes = st.modes
        a, o, _n = plane
        ci, cj, ck = letters
        inch = modes["units"] == 70
        pitch = params[ck][0] if ck in params else None
        sp = (cur_part[a], cur_part[o])
        ccw = mode == 3
        try:
            if by_centre:
                di = params[ci][0] if ci in params else 0.0
                dj = params[cj][0] if cj in params else 0.0
                if inch:   # self.length() of a centre word
                    di *= INCH
                    dj *= INCH
                center = (di, dj) if modes["arc_centre"] == 261 else (sp[0] + di, sp[1] + dj)
                st.arc_radius = None   # an arc by its centre clears the stored radius (L6533)
            else:
                r = params["R"][0]
                if inch:
                    r *= INCH
                center = arcs.centre_from_radius(sp, (end_part[a], end_part[o]), r, not ccw)
        except arcs.ArcError as exc:
            raise InterpError("INT064", str(exc), _first_col(words, params)) from None
        ep = (end_part[a], end_part[o])
        r0 = math.dist(sp, center)
        if r0 < 1e-9:
            raise InterpError("INT061", "the arc centre is on the start point (radius 0)", _first_col(words, params))
        programmed = center
        radius = math.dist(ep, center)   # the record's radius while the centre and the end stay
        if by_centre and not (mismatch := abs(radius - r0)) <= 1e-12:   # else _radius_check() keeps the centre
            # _radius_check() of the radii worked out already: CIRINERR, CIRINFACT (it says INT062), G264/G265
            if not (mismatch <= self._cirinerr or 100.0 * mismatch / r0 <= self._cirinfact):
                iso._radius_check(sp, ep, center, _first_col(words, params))
            if modes["centre_correction"] == 265:
                center = arcs.corrected_centre(sp, ep, center)
                if center is not programmed:
                    radius = math.dist(ep, center)
        st.arc_data = (sp, programmed, center, ep, plane)   # arc_data(): V.G.R, I, J, K, CIRERR (L40454)
        delta = arcs.sweep(sp, ep, center, ccw)
        turns = 0
        if pitch is not None:
            delta, turns, ep = iso._helix(delta, pitch, cur_part, end_part, center, r0, ccw, _first_col(words, params))
            end_part[a], end_part[o] = ep
            radius = math.dist(ep, center)
        applied = st.length_offset
        if applied or (st.offset and st.tool):   # _length_compensation() returns at once otherwise
            iso._length_compensation(_Words(words))
            if st.length_offset is not applied:
                off = st.offsets()
        # arcs.end_tangent(), inline: math.dist() of two points is math.hypot() of their differences
        ra, ro = ep[0] - center[0], ep[1] - center[1]
        st.tangent = None if radius < 1e-12 else (-ro / radius, ra / radius) if ccw else (ro / radius, -ra / radius)
        end = _machine_end(st, end_part, off)
        lower, upper = st.lower_limits, st.upper_limits
        for x, v in end.items():   # check_limits() says more only for a point outside the limits
            if not lower[x] - 1e-9 <= v <= upper[x] + 1e-9:
                iso.interp.check_limits(end, _first_col(words, params), start)
                break
        st.machine_pos = dict(end)   # moved_to()
        st._last_end = end
        center_part = {a: center[0], o: center[1]}
        center_m = {a: center[0] + 0.0, o: center[1] + 0.0} if off is None else \
            {a: center[0] + off[a], o: center[1] + off[o]}
        # the squares of the moves off the plane: sum(), as Arc.length sums (compensated from Python 3.12 on: a
        # loop of += would differ), of a list made by a loop (the same sum, without a comprehension's function)
        squares = []
        for x, v in end.items():
            if x != a and x != o:
                squares.append((v - start[x]) ** 2)
        other = sum(squares)
        mode_f = modes["feed"]
        feed = st.feed
        if mode_f == 94 and feed:   # _active_feed() of G94 with a feed: F itself at most MAXFEED, whatever the length
            if self._max_feed > 0:
                feed = min(feed, self._max_feed)
        else:
            planar = abs(math.radians(delta)) * r0 * 1.0   # the scale is 1
            feed = iso._active_feed(math.hypot(planar, math.sqrt(other)), start)
        css = iso._css() if mode_f == 95 else None
        radius *= 1.0   # the scale is 1
        if css is None and feed is not None and pitch is None and end is end_part and start[a] is sp[0] \
                and start[o] is sp[1]:
            # record_time() of the record: Arc.sweep is delta, the sweep of the same points (the centre's + 0.0
            # turns only a -0.0 into 0.0, which changes the sweep only for an end on the centre, where the radius
            # 0 makes the planar length 0 whatever the sweep), then Arc.length's arithmetic
            length = math.hypot(abs(math.radians(delta)) * radius, math.sqrt(other))
            self.seconds = 0.0 if length == 0.0 else length / feed * 60.0 if feed else 0.0
        dyn = st._dynamics   # st.dynamics(): no per-block modes in the simplest state
        # Arc's fields in order: kind, start, end, end_part, center, center_part, direction, plane, radius, turns,
        # feed, feed_mode, src, comp, dyn, frame, joins, css
        return _arc_record("arc", start, end, end_part, center_m, center_part, "ccw" if ccw else "cw", plane, radius,
                           turns, feed, _FEED_MODES.get(mode_f) or feed_mode(mode_f), src, None,
                           dyn if dyn is not None else st.dynamics(), None,
                           _JOINS.setdefault(joins := (modes["transition"], modes["comp_start"]), joins), css)


def record_maker(cls):
    """A function that makes ``cls(**fields)`` without its ``__init__``, to an object that compares, hashes and
    prints the same: a frozen dataclass with slots sets each field through ``object.__setattr__``, and a
    slot's descriptor called from Python costs as much; this fills the slots of a twin class (the same bases
    and slots, without the frozen ``__setattr__``: each field a plain slot store) and then makes the object a
    ``cls`` (``__class__`` assignment between classes of the same layout), a quarter of the cost.  Called
    with the fields in their order or by keyword (a positional call costs less: the plain blocks' records);
    the fields left out take their defaults.  ``cls`` itself when it is not such a class (a
    ``__post_init__``, a default factory, no slots, another layout)."""
    if not dataclasses.is_dataclass(cls) or hasattr(cls, "__post_init__") or "__slots__" not in cls.__dict__:
        return cls
    fields = dataclasses.fields(cls)
    if any(f.default_factory is not dataclasses.MISSING or not f.init for f in fields):
        return cls
    twin = type(f"_{cls.__name__}Slots", cls.__bases__, {"__slots__": cls.__slots__})
    try:
        object.__new__(twin).__class__ = cls
    except TypeError:   # not the same layout
        return cls
    space = {"_new": object.__new__, "_twin": twin, "_cls": cls}
    params, body = [], []
    for i, f in enumerate(fields):
        if f.default is dataclasses.MISSING:
            params.append(f.name)
        else:
            space[f"_default{i}"] = f.default
            params.append(f"{f.name}=_default{i}")
        body.append(f"    o.{f.name} = {f.name}\n")
    code = f"def make({', '.join(params)}):\n    o = _new(_twin)\n{''.join(body)}    o.__class__ = _cls\n    return o\n"
    exec(code, space)   # the code is made here, from the field names of a class of records
    return space["make"]


_line_record = record_maker(Line)
_arc_record = record_maker(Arc)
_source = record_maker(Source)


def _literal_words(items: tuple) -> bool:
    """Whether each of a block's ``items`` is a :class:`Word` of a literal value (not an expression, a
    parameter, a word without a value or G159=n), as the words of :class:`PlainWords` are."""
    return all(type(w) is Word and type(w.value) is float and w.eq is None for w in items)


def _first_col(words: dict, params: dict) -> int:
    """The column an arc's errors point at: that of its first axis word, else of its first centre or radius word."""
    return next(iter(words.values()))[1] if words else next(iter(params.values()))[1]


def _part_point(st, pos: dict) -> tuple:
    """``(off, cur_part)``: :meth:`~fagorcnc.interp.state.ChannelState.offsets` and the part position
    (``programmed_pos()`` under no transformation); ``off`` is None when every offset is 0.0 (no fixture,
    no tool length applied, origins and additive origins 0), and ``cur_part`` then ``pos`` itself, not to
    be changed: ``x - 0.0`` is ``x`` (a copy where the machine position's axes are not in the channel's
    order)."""
    if not st.fixture and not st.length_offset and not any(st.abs_offset.values()) \
            and not any(st.inc_offset.values()):   # offsets(): 0.0 + 0.0 + 0.0 + 0.0 on every axis
        axes = st.axes
        if len(pos) == len(axes) and list(pos) == axes:
            return None, pos
        return None, {x: pos[x] for x in axes}
    off = st.offsets()
    return off, {x: pos[x] - off[x] for x in st.axes}


def _machine_end(st, end_part: dict, off: dict | None) -> dict:
    """``to_machine()`` then ``shared_end()`` of a move's end point, ``off`` as :func:`_part_point` gives it:
    with no offset, ``end_part`` itself (``v + 0.0 == v``), unless a NaN is among its coordinates."""
    if off is None:
        total = sum(end_part.values())
        if total == total:   # no NaN: every v + 0.0 equals v, shared_end() keeps end_part
            return end_part
        off = st.offsets()
    end = {x: v + off[x] for x, v in end_part.items()}
    return end_part if end == end_part and tuple(end) == tuple(end_part) else end


class _Words:
    """The axis words of a block, as ``IsoExecutor._length_compensation`` reads a :class:`BlockWords`."""

    __slots__ = ("axes",)

    def __init__(self, axes: dict) -> None:
        self.axes = axes
