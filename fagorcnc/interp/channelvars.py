"""Channel variables of the catalogue's remainder (issue 26 item 10; seed 002 ch. 22; spec 08 B.8, B.15).

* ``V.G.DYNOVR`` (L36672-L36716): one percentage applied to the dynamics of every axis of the channel, in
  real time (the look-ahead does not see it coming: its read and write stop block preparation), bounded by
  the machine parameters MINDYNOVR and MAXDYNOVR (L20408-L20418);
* ``V.G.ENDREP`` / ``V.G.SPDLREP`` (L41724-L41740): the repositioning after a tool inspection;
* ``V.G.HSC`` (L40709) and ``V.G.CONTERROR`` (L36584): the HSC mode and its programmed error;
* ``V.G.PENDRPT`` (L40656): the repetitions of ``#RPT`` still to run; ``V.G.INTMAN`` (L39452): manual moves
  allowed (G201 active; offline there is no manual mode, TEACH-IN or tool inspection);
* ``V.E.PROGSELECT`` (L43316, spec 08 B.23): written with 0 only, no effect offline.
"""

from __future__ import annotations

from .expressions import InterpError, whole


class ChannelVariables:
    """The variables above, as ``Variables.plain_vars`` entries."""

    def __init__(self, variables) -> None:
        self.v = variables
        self.state = variables.state

    def plain(self) -> dict:
        s = self.state
        return {
            "V.G.DYNOVR": (lambda i: s.dynamic_override, self._set_dynovr),
            # no tool inspection offline: the axes are where the program left them, all repositioned (L41724)
            "V.G.ENDREP": (lambda i: s.repositioning[0], self._set_endrep),
            "V.G.SPDLREP": (lambda i: s.repositioning[1], self._set_spdlrep),
            "V.G.HSC": (lambda i: 0.0 if s.hsc is None else 1.0, None),
            "V.G.CONTERROR": (self._conterror, None),
            # states a running program reads in a known way offline: fagorcnc refuses a move beyond a software
            # limit before it runs (no limit is ever reached, L33055); it runs a #MOVE before the blocks after it
            # (no independent axis is moving at a synchronisation point, L41915); an error stops the program
            # (the channel has none while it runs, L41658)
            "V.G.SOFTLIMIT": (lambda i: 0.0, None),
            "V.G.IBUSY": (lambda i: 0.0, None),
            "V.G.CNCERR": (lambda i: 0.0, None),
            "V.G.VIRTAXST": (lambda i: 0.0, None),   # #VIRTAX ON is refused (not computed): never active (L42433)
            # the NR repetitions still to run: n - 1 during the first, 0 during the last (L40680-L40684); read
            # in the modal subroutine (#MCALL) each repetition calls
            "V.G.PENDNR": (lambda i: float(s.pending_nr), None),
        }

    def axis(self) -> dict:
        """``V.A.INPOS.xn`` (L39865): its read stops preparation, so the axes have reached the position.

        The coarse and fine parts of the origin offsets (L35243-L35340): fagorcnc's machine has no fine
        adjustment (MPG.FINEORG 0, L19265), so the coarse part is the whole offset and the fine part 0."""
        orgt = self.v.axis_vars["V.A.ORGT[]"]
        return {
            "V.A.INPOS": (lambda st, i, a: self.v._unit(a), None),   # 1: get() divides by the unit
            "V.A.COARSEORG": (lambda st, i, a: st.abs_offset[a], None),
            "V.A.FINEORG": (lambda st, i, a: 0.0, None),
            "V.A.COARSEORGT[]": orgt,
            "V.A.FINEORGT[]": (lambda st, i, a: orgt[0](st, i, a) * 0.0, self._set_fine),
        }

    @staticmethod
    def _set_fine(st, index: tuple, axis: str, value: float) -> None:
        if value:
            raise InterpError("INT258", f"V.A.FINEORGT[{index[0]}].{axis} = {value:g}: this machine has no fine "
                              "adjustment of the origin offsets (MPG.FINEORG 0, seed 002 L19265); write V.A.ORGT", 1)

    @staticmethod
    def spindle() -> dict:
        """``V.A.CNCSSO.S`` (L37274): the panel's spindle override; no panel offline: 100 %, as V.G.CNCFRO."""
        return {"CNCSSO": lambda sp: 100.0}

    #: read and written at execution: they stop block preparation (L36674, L41726, L41736, L36586, L39454)
    EXECUTION = frozenset({"V.G.DYNOVR", "V.G.ENDREP", "V.G.SPDLREP", "V.G.CONTERROR", "V.G.INTMAN",
                           "V.G.SOFTLIMIT", "V.G.IBUSY", "V.A.INPOS", "CNCSSO", "V.A.COARSEORGT[]",
                           "V.A.FINEORGT[]"})

    # ------------------------------------------------------------ DYNOVR
    def _bound(self, name: str) -> float:
        value = self.state.machine.machine_parameters.get((name, (), None))
        if value is None:
            raise InterpError("INT257", f"V.G.DYNOVR is bounded by the machine parameters MINDYNOVR and MAXDYNOVR "
                              f"(seed 002 L36714), and this machine file does not give {name}: "
                              f"[machine_parameters] \"MPG.{name}\" = %", 1)
        return value

    def _set_dynovr(self, index: tuple, value: float) -> None:
        """The percentage of the axes' feed, acceleration and jerk limits the next blocks are planned with:
        the read or write stops preparation, so the blocks after it see it (L36708-L36710)."""
        low, high = self._bound("MINDYNOVR"), self._bound("MAXDYNOVR")
        if not low <= value <= high or not value > 0:
            raise InterpError("INT256", f"V.G.DYNOVR = {value:g} %: the machine parameters allow "
                              f"{low:g} (MINDYNOVR) to {high:g} % (MAXDYNOVR), seed 002 L36714", 1)
        st = self.state
        st.dynamic_override = float(value)
        st.dynamics_changed()

    # ------------------------------------------------------------ repositioning
    def _set_endrep(self, index: tuple, value: float) -> None:
        if value not in (0, 1):
            raise InterpError("INT045", f"V.G.ENDREP = {value:g}: 1 all axes repositioned, 0 not (L41730)", 1)
        self.state.repositioning = (float(value), self.state.repositioning[1])

    def _set_spdlrep(self, index: tuple, value: float) -> None:
        n = whole(value)
        if n is None or n < 0:
            raise InterpError("INT045", f"V.G.SPDLREP = {value:g}: the M function that repositions the spindle "
                              "is a whole number (L41738)", 1)
        self.state.repositioning = (self.state.repositioning[0], float(n))

    # ------------------------------------------------------------ HSC
    def _conterror(self, index: tuple) -> float:
        """The error programmed with #HSC ON (mm, inches under G70); 0 without HSC."""
        hsc = self.state.hsc
        return 0.0 if hsc is None else hsc.tolerance / self.v._unit()


def interpreter_variables(interp) -> dict:
    """The variables that read the interpreter's own state (its frames, the manual intervention)."""

    def pending_repeats(index: tuple) -> float:
        """The innermost #RPT of the running program or subroutine: n - 1 on the first pass, 0 on the last
        (L40664-L40668); 0 outside a repetition."""
        frame = interp.frames[-1] if interp.frames else None
        repeat = frame.repeat if frame is not None else None
        return float(repeat[2] - 1) if repeat is not None else 0.0

    def progselect(index: tuple, value: float) -> None:
        if value != 0:
            raise InterpError("INT045", f"V.E.PROGSELECT = {value:g}: a program writes it with 0 only, to clear the "
                              "program selected in automatic mode (seed 002 L43316)", 1)

    def read_progselect(index: tuple) -> float:
        raise InterpError("INT241", "V.E.PROGSELECT is read by the interface only; a program writes it with 0 "
                          "(seed 002 L43316)", 1)

    return {
        "V.G.PENDRPT": (pending_repeats, None),
        # G201's additive intervention lets the operator move the axes by hand (L39465); G200 stops the program
        "V.G.INTMAN": (lambda i: 1.0 if interp.manual.additive else 0.0, None),
        "V.E.PROGSELECT": (read_progselect, progselect),
    }
