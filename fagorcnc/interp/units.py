"""Units the interpreter converts at its edges: it keeps millimetres inside (spec 02 §1)."""

#: mm per inch (G70, seed 002 L2420)
INCH = 25.4
