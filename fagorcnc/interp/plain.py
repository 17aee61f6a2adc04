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
the general way.  ``tests/test_plain_blocks.py`` runs programs both ways and compares everything.
"""

from __future__ import annotations

from ..syntax.ast import Block, Word
from . import compat
from .words import BlockWords

#: What :meth:`PlainBlocks.run` returns for a block it does not take: the general executor runs it.
NOT_PLAIN = object()

#: G functions a plain block may hold: their number and modal group (``gtable.G_FUNCTIONS``).
_PLAIN_G = {0.0: (0, "motion"), 1.0: (1, "motion"), 2.0: (2, "motion"), 3.0: (3, "motion"),
            90.0: (90, "distance"), 91.0: (91, "distance")}
#: Letters of a plain block that are the parameters of its motion (arc centre, radius).
_PLAIN_PARAMS = frozenset("IJKR")
#: The largest block number (``Evaluator.integer``'s range for N).
_MAX_N = 4294967295.0
#: Feed modes whose moves are not checked against a stopped spindle (as ``IsoExecutor.execute``).
_NO_SPINDLE_LINT = ("G95", "G33", "G63")


class PlainBlocks:
    """Runs plain blocks for an :class:`~fagorcnc.interp.interpreter.Interpreter` (see the module)."""

    __slots__ = ("interp", "iso", "state")

    def __init__(self, interp) -> None:
        self.interp = interp
        self.iso = interp.iso
        self.state = interp.state

    def run(self, block: Block):
        """The record of ``block`` (None when it moves nothing, as ``F800`` alone), or :data:`NOT_PLAIN`
        when it is not a plain block.  Raises the general path's :class:`InterpError` where it would."""
        st = self.state
        interp = self.interp
        channel = st.channel
        if interp.modal_call is not None or st.mcs_on or st.cycles.active is not None or channel.links \
                or channel.parked:
            return NOT_PLAIN   # #MCALL after the move, #MCS, a canned cycle, coupled or parked axes
        by_name = channel.by_name
        machine_axes = st.machine.axes
        axes: dict = {}
        params: dict = {}
        gl: list = []
        groups = 0   # bit 1: a motion G, bit 2: a G90/G91 (two of one group: the general path says)
        motion = None
        feed = None
        number = None
        for w in block.items:
            if type(w) is not Word:
                return NOT_PLAIN
            addr, value, col, eq = w
            if type(value) is not float or eq is not None:
                return NOT_PLAIN   # an expression, a parameter, a word without a value, G159=n
            if addr == "G":   # G, N and F before the axes, in classify()'s order
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
            elif addr == "N":
                if not (0.0 <= value <= _MAX_N and value.is_integer()):
                    return NOT_PLAIN   # INT036, INT037
                number = value
            elif addr == "F":
                feed = (value, col)   # the last F counts, as in classify()
            elif (axis := by_name.get(addr)) is not None:
                if axis in axes:
                    return NOT_PLAIN   # INT023
                axes[axis] = (value, col)
            elif addr in _PLAIN_PARAMS and addr not in machine_axes:
                if addr in params:
                    return NOT_PLAIN   # INT023
                params[addr] = (value, col)
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
        text = block.text
        for (n, _group), col in gl:
            if n >= 10:
                compat.leading_zero(interp, n, col, text)   # "G090" is G90
        iso = self.iso
        iso.sync.previous_motion = modes["motion"]   # G33 joins the thread of the block before (L7366)
        gs = {}
        for (n, group), col in gl:
            gs[n] = (col, None)
            modes[group] = n
        st.block_modes = {}
        bw = BlockWords()
        bw.g = [(n, col, None) for (n, _group), col in gl]
        bw.axes = axes
        bw.params = params
        bw.feed = feed
        if feed is not None:
            iso._feed(*feed)
        rec = iso._motion(gs, bw, interp._src(block))
        if rec is not None and rec.kind != "rapid" and rec.feed_mode not in _NO_SPINDLE_LINT:
            compat.spindle_lint(interp, rec, 1)
        return rec
