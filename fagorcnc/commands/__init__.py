"""The user's commands, one module each: ``run``, ``check``, ``plot``, ``parse``, ``emulate``.

Each module holds the library function behind its command (``run()``, ``check_file()``,
``plot_program()``) and the handler :mod:`fagorcnc.cli` wires to the command line.  No pipeline
stage imports this package.
"""
