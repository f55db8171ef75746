#!/usr/bin/env python3
"""Independent reading of testpiece's G-code (ISO / Fanuc / LinuxCNC dialects) by two kept
PyPI parsers, for tests/it/program_parsers.rs.

- pygcode (RS274/NGC words and modal groups as LinuxCNC defines them): every line must parse;
  every G and M word must be one pygcode knows (an unknown one is left in `modal_params`); its
  interpreter (`pygcode.Machine`, axes X Y Z A B C) runs every block, and the axis values
  after each motion block (G00/G01, not G53) are printed.
- gcodeparser: every G/M/T command line is found, and its G00/G01 lines are counted.

Usage: check_gcode.py FILE
A block with a word pygcode does not know (listed in "unknown") is not run by the interpreter.
Prints one JSON object: {"lines", "gcodes": [...], "unknown": [...], "moves": [[line, rapid,
X, Y, Z, A, B, C], ...], "gcodeparser_moves": n}. Exit 1 on a parse error (message on stderr).
"""
import json
import sys

import gcodeparser
import pygcode
from pygcode import Line, Machine


class FiveAxis(Machine):
    axes = set("XYZABC")


def main():
    path = sys.argv[1]
    text = open(path, encoding="ascii").read()
    m = FiveAxis()
    gcodes, unknown, moves = set(), [], []
    for n, raw in enumerate(text.splitlines(), 1):
        try:
            line = Line(raw)
        except Exception as e:  # noqa: BLE001 - any failure is the finding
            print(f"line {n}: pygcode: {type(e).__name__}: {e}: {raw!r}", file=sys.stderr)
            sys.exit(1)
        for w in line.block.modal_params:
            if w.letter in "GM":
                unknown.append([n, str(w)])
        names = [type(g).__name__ for g in line.block.gcodes]
        gcodes.update(names)
        if unknown and unknown[-1][0] == n:
            continue  # a block with a word pygcode cannot run (the allowed TCP words)
        in_machine = "GCodeMoveInMachineCoords" in names
        m.process_block(line.block)
        motion = [g for g in line.block.gcodes if type(g).__name__ in ("GCodeRapidMove", "GCodeLinearMove")]
        if (motion or any(w.letter in "XYZABC" for w in line.block.modal_params)) and not in_machine:
            p = m.pos.values
            rapid = type(m.mode.motion).__name__ == "GCodeRapidMove"
            moves.append([n, rapid] + [p.get(a, 0.0) for a in "XYZABC"])
    gp = [l for l in gcodeparser.parse_gcode_lines(text) if l.command in (("G", 0), ("G", 1))]
    print(json.dumps({"lines": n, "gcodes": sorted(gcodes), "unknown": unknown, "moves": moves,
                      "gcodeparser_moves": len(gp), "pygcode": getattr(pygcode, "__version__", "?")}))


if __name__ == "__main__":
    main()
