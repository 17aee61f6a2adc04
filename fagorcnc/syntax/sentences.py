"""Catalogue of the ``#`` sentences of the manual (seed 002 L1602-L1767, ch. 21.1).

The grammar reads every sentence generically (keyword + items); this table
says which keywords exist and, where the manual requires one, which keyword
must follow (``#HSC ON``/``#HSC OFF``, ``#KIN ID``, ``#TOOL AX``...).
``#CALL``, ``#PCALL``, ``#MCALL`` and ``#RPT`` have rules of their own in the
grammar.  ``None`` means the arguments are free-form for the parser (their
meaning is checked by the interpreter).
"""

from __future__ import annotations

from .ast import Keyed, Name, Sentence

#: keyword -> allowed first keyword (a frozenset), or None when not constrained.
SENTENCES: dict[str, frozenset | None] = {
    "ABORT": None,                                   # 13.3
    "ACS": None,                                     # 17.3
    "ANGAX": frozenset({"ON", "OFF", "SUSP"}),       # 15.1, 15.2
    "ASPLINE": frozenset({"ENDTANG", "MODE", "STARTTANG"}),  # 21.1.13
    "AXIS": None,                                    # 8.9
    "CALL AX": None,                                 # 21.1.8
    "CALL SP": None,                                 # 21.1.9
    "CAM": frozenset({"ON", "OFF", "SELECT", "DESELECT"}),  # 21.1.20
    "CAX": None,                                     # 14.1
    "CD": frozenset({"ON", "OFF"}),                  # 21.1.12
    "CLEAR": None,                                   # 21.1.18
    "COMMENT": frozenset({"BEGIN", "END"}),          # 1.8
    "CONTJOG": None,                                 # 8.9.3
    "CS": None,                                      # 17.3
    "CYL": None,                                     # 14.3
    "DEF": None,                                     # 21.1.16
    "DELETE": None,                                  # 1.9 (at least one variable)
    "DFHOLD": None, "EFHOLD": None,                  # 21.1.5
    "DGWZ": None,                                    # 21.1.4
    "DSBLK": None, "ESBLK": None,                    # 21.1.5
    "DSTOP": None, "ESTOP": None,                    # 21.1.5
    "ERROR": None,                                   # 21.1.1
    "EXBLK": None,                                   # 13.2
    "EXEC": None,                                    # 13.1
    "FACE": None,                                    # 14.2
    "FLUSH": None,                                   # 21.1.21
    "FOLLOW": frozenset({"ON", "OFF"}),              # 21.1.19
    "FREE": frozenset({"AX", "SP"}),                 # 21.1.8, 21.1.9
    "HSC": frozenset({"ON", "OFF"}),                 # 18.2-18.4
    "INCJOG": None,                                  # 8.9.3
    "INIT": frozenset({"MACROTAB"}),                 # 21.1.16
    "KIN": frozenset({"ID"}),                        # 17.2
    "LINK": None, "UNLINK": None,                    # 21.1.6
    "MASTER": None,                                  # 7.1.1
    "MCS": None,                                     # 5.1
    "MDOFF": None,                                   # 12.3.6
    "MEET": None,                                    # 21.1.18
    "MOVE": None,                                    # 21.1.19
    "MPG": None,                                     # 8.9.3
    "MSG": None,                                     # 21.1.3
    "PARK": None, "UNPARK": None,                    # 21.1.7
    "PATH": None,                                    # 12.4
    "POLY": None,                                    # 21.1.14
    "PROBE": None,                                   # probing manual
    "PWMOUT": frozenset({"ON", "OFF"}),              # 19.2
    "RENAME": frozenset({"AX", "SP"}),               # 21.1.8, 21.1.9
    "REPOS": None,                                   # 12.8.1
    "RET": None,                                     # 12.2
    "RETDSBLK": None,                                # 12.3.7
    "ROTATEMZ": None,                                # 6.4
    "ROUNDPAR": None,                                # 9.3.1
    "RTCP": frozenset({"ON", "OFF"}),                # 17.6
    "SCALE": None,                                   # 9.10
    "SELECT": frozenset({"PROBE"}),                  # probing manual
    "SERVO": frozenset({"ON", "OFF"}),               # 21.1.11
    "SET": frozenset({"AX", "SP", "OFFSET"}),        # 21.1.8, 21.1.9, 8.9.3
    "SIGNAL": None,                                  # 21.1.18
    "SLOPE": None,                                   # 21.1.15
    "SPLINE": frozenset({"ON", "OFF"}),              # 21.1.13
    "SWTOUT": frozenset({"ON", "OFF"}),              # 19.1
    "SYNC": None,                                    # 21.1.10, 8.9.3 (#SYNC POS)
    "TANGCTRL": frozenset({"ON", "OFF", "SUSP", "RESUME"}),    # 16.1, 16.2 (RESUME: L12320)
    "TANGFEED": frozenset({"RMIN"}),                 # 6.2.3
    "TCAM": frozenset({"ON"}),                       # 21.1.20
    "TFOLLOW": frozenset({"ON"}),                    # 21.1.19
    "TIME": None,                                    # 10.1
    "TLC": None,                                     # 17.7
    "TOOL": frozenset({"AX", "ORI"}),                # 4.4, 17.5
    "TSYNC": None,                                   # 21.1.10
    "UNSYNC": None,                                  # 21.1.10
    "VIRTAX": frozenset({"ON", "OFF"}),              # 20.1, 20.2
    "WAIT": None,                                    # 21.1.18, 21.1.21 (#WAIT FOR)
    "WARNING": None, "WARNINGSTOP": None,            # 21.1.2
}

#: Sentences that take no argument at all.
NO_ARGUMENTS = frozenset({"RET", "RETDSBLK", "MDOFF", "FLUSH", "DSBLK", "ESBLK",
                          "DSTOP", "ESTOP", "DFHOLD", "EFHOLD"})


def _first_keyword(node: Sentence) -> str | None:
    if node.args and type(node.args[0]) in (Name, Keyed):
        return node.args[0].name
    return None


def check_sentence(node: Sentence) -> list:
    """Problems ``(col, code, message)`` with a generic sentence's keywords."""
    kw = node.keyword
    if kw not in SENTENCES:
        return [(node.col, "SYN012", f"unknown sentence #{kw}")]
    allowed = SENTENCES[kw]
    if allowed is not None:
        first = _first_keyword(node)
        if first not in allowed:
            choices = " or ".join(f"#{kw} {a}" for a in sorted(allowed))
            got = f"'{first}'" if first else "nothing"
            return [(node.col, "SYN013", f"#{kw} needs {choices}; found {got}")]
    if kw in NO_ARGUMENTS and node.args:
        return [(node.col, "SYN002", f"#{kw} takes no arguments")]
    if kw == "DELETE" and not node.args:
        # seed 002 L1844: #DELETE must name at least one variable
        return [(node.col, "SYN013", "#DELETE must name at least one variable")]
    return []
