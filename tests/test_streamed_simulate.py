"""Issue 27 memory and read work: the syntax pre-pass without word splitting, simulate() streamed."""

from __future__ import annotations


def test_structure_only_lines_keep_the_diagnostics_of_the_whole_file():
    # the syntax pre-pass of a dry run skips the items of plain word blocks without an M, but not
    # the M17 that ends a local subroutine: the same diagnostics with and without structure_only
    from fagorcnc.syntax import iter_lines
    from fagorcnc.syntax.structure import assemble

    for text in ("%L SUB\nG1 X1 Y2 F100\nM17\n%MAIN\nN10 G1 X1\nN10 G1 X2\nL SUB\nM30\n",
                 "%L SUB\nG1 X1 Y2 F100\n%MAIN\nG1 X1\nM30\n",
                 "G1 X1 F100\n$IF P1 == 1\nG1 X2\nM30\n"):
        full = assemble(iter_lines(text), "<t>", keep_body=False).diagnostics
        quick = assemble(iter_lines(text, structure_only=True), "<t>", keep_body=False).diagnostics
        assert [(d.line, d.code) for d in quick] == [(d.line, d.code) for d in full]
    codes = {d.code for d in assemble(iter_lines("%L SUB\nG1 X1 Y2 F100\n%MAIN\nG1 X1\nM30\n",
                                                 structure_only=True), "<t>", keep_body=False).diagnostics}
    assert "STR003" in codes   # the subroutine without M17 is still found


def test_simulate_streams_a_clean_program_and_parses_it_again_when_asked(tmp_path):
    # the records and the verdict are those of the whole-program run; Result.program is parsed on use
    import fagorcnc
    from fagorcnc.config.machine import load_machine
    from fagorcnc.program_files import resolve
    from fagorcnc.simulate import _simulate_whole

    f = tmp_path / "p.nc"
    f.write_text("%PART\nG90 G1 X0 Y0 F1000\nN10 G1 X10\nG2 X20 Y0 I5 J0\n$GOTO N30\nG1 X99\nN30 G1 Y5\nM30\n")
    streamed = fagorcnc.simulate(f)
    whole = _simulate_whole(resolve(f), load_machine(None), False)
    assert streamed.moves == whole.moves and streamed.cycle_time == whole.cycle_time
    assert [str(d) for d in streamed.diagnostics] == [str(d) for d in whole.diagnostics]
    assert (streamed.ok, streamed.ended_by, streamed.ending) == (whole.ok, whole.ended_by, whole.ending)
    assert "_program" in vars(streamed) and callable(vars(streamed)["_program"])   # not parsed yet
    assert streamed.program == whole.program and streamed.program.name == "PART"
    bad = fagorcnc.simulate(text="G1 X1 F100\nG1 X[[\nM30\n")   # a syntax error: parsed whole, not started
    assert not bad.ok and bad.moves == [] and bad.program is not None and not bad.program.ok


def test_repeated_coordinates_share_one_float_in_the_parser():
    # a raster repeats its X values every row: the parser keeps one float object per number text, with
    # the sign (X-1.5 is -1.5, not 1.5), and the table stays bounded however many numbers a program has.
    # simulate() keeps the coordinates of plain moves as 8-byte doubles in columns (interp/movestore.py):
    # the records it gives back are equal to the interpreter's, their floats not the same objects
    import fagorcnc
    from fagorcnc.syntax import builder

    first, again = builder.split_words("X-1.5", 1)[0].value, builder.split_words("X-1.5", 1)[0].value
    assert first is again and first == -1.5 and builder.split_words("X1.5", 1)[0].value == 1.5
    r = fagorcnc.simulate("G90 G1 X0 Y0 F1000\nX-1.5 Y2\nX3 Y2\nX-1.5 Y4\nX3 Y4\nM30\n")
    moves = [m for m in r.moves if m.kind == "linear"]
    assert moves[1].end["X"] == -1.5 and moves[3].end["X"] == -1.5 and moves[2].end["X"] == 3.0
    assert moves[1].end["Y"] == moves[2].end["Y"] == 2.0
    fagorcnc.simulate("".join(f"G1 X{i * 0.001:.3f}\n" for i in range(2 * builder._NUMBERS_MAX)) + "M30\n")
    assert len(builder._NUMBERS) <= builder._NUMBERS_MAX
