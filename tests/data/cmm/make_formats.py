#!/usr/bin/env python3
"""Writes tests/data/cmm/formats/: example_clean.csv (tests/data/reference/examples/) rewritten in
every format of shared/spec/cmm-csv.md. Independent of the Rust reader (plain Python, decimal
text manipulation), so that `tests/it/cmm_formats.rs` checks the reader against it.

Numbers: where a format keeps the canonical text (6 decimals for positions and deviations, 9 for
normals) the text is copied or its decimal point shifted exactly (mm -> um: Decimal * 1000).
Measured positions are made from the exact nominal points of tests/data/reference/points.csv
(full double precision): measured = P + deviation * N, written with repr() (17 significant
digits), so that projecting them back recovers the deviation to ~1e-12 mm.

Run from the repository root: python3 tests/data/cmm/make_formats.py
"""
import csv
from decimal import Decimal
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
OUT = ROOT / "tests/data/cmm/formats"
rows = list(csv.DictReader(open(ROOT / "tests/data/reference/examples/example_clean.csv")))
exact = list(csv.DictReader(open(ROOT / "tests/data/reference/points.csv")))
assert [r["id"] for r in rows] == [e["id"] for e in exact]
AX = ("x", "y", "z")
NX = ("nx", "ny", "nz")


def um(text):
    """mm text -> um text, exactly (decimal shift)."""
    return format(Decimal(text) * 1000, "f")


def comma(text):
    return text.replace(".", ",")


def measured(k):
    e = exact[k]
    d = float(rows[k]["deviation"])
    return [repr(float(e[a]) + d * float(e[n])) for a, n in zip(AX, NX)]


def write(name, text, encoding="utf-8"):
    (OUT / name).write_bytes(text.encode(encoding))


def table(header, lines, sep):
    return sep.join(header) + "\n" + "".join(sep.join(l) + "\n" for l in lines)


canon = [[r["id"], r["curve"]] + [r[a] for a in AX] + [r[n] for n in NX] + [r["deviation"]] for r in rows]
H = ["id", "curve", "x", "y", "z", "nx", "ny", "nz", "deviation"]

# 1. semicolon + decimal comma (European Excel)
write("clean_semicolon_decimal_comma.csv", table(H, [[comma(f) for f in l] for l in canon], ";"))
# 2. deviation in um (header unit), plus an extra tolerance column and comment lines
lines = [l[:8] + [um(l[8]), "0.05", "ok" if k % 7 else "check"] for k, l in enumerate(canon)]
write(
    "clean_um_extra_columns.csv",
    "# exported by a CMM, deviation in micrometres\n// second comment style\n\n"
    + table(["Point", "Curve", "X_nom", "Y_nom", "Z_nom", "I", "J", "K", "Dev [um]", "Tol", "Comment"], lines, ","),
)
# 3. measured coordinates only (rule 3)
lines = [[r["id"], r["curve"]] + measured(k) for k, r in enumerate(rows)]
write("clean_measured_only.csv", table(["id", "curve", "x_meas", "y_meas", "z_meas"], lines, ","))
# 4. nominal + measured, no deviation (rule 2), exact nominal points
lines = [[r["id"]] + [exact[k][a] for a in AX] + measured(k) for k, r in enumerate(rows)]
write("clean_nominal_measured.csv", table(["id", "x", "y", "z", "actual x", "actual y", "actual z"], lines, ","))
# 5. nominal + measured + deviation (rule 4)
lines = [[r["id"]] + [exact[k][a] for a in AX] + measured(k) + [r["deviation"]] for k, r in enumerate(rows)]
write("clean_nominal_measured_dev.csv", table(["id", "x", "y", "z", "xm", "ym", "zm", "dev"], lines, ","))
# 6. PowerInspect ASCII
lines = [
    " ".join([f"P{r['id']}"] + [r[a] for a in AX] + [r[n] for n in NX] + [r["deviation"], "-0.050", "0.050"])
    for r in rows
]
write("clean_powerinspect.txt", "\n".join(lines) + "\n")
# 7. PC-DMIS XYZIJK, METRIC, with deviation
lines = [",".join([r[a] for a in AX] + [r[n] for n in NX] + [r["deviation"]]) for r in rows]
write("clean_xyzijk_metric.txt", "XYZIJK    METRIC\n" + "\n".join(lines) + "\n")
# 8. PC-DMIS XYZIJK, INCH, with deviation (lengths / 25.4 written with repr)
inch = lambda t: repr(float(t) / 25.4)
lines = [",".join([inch(r[a]) for a in AX] + [r[n] for n in NX] + [inch(r["deviation"])]) for r in rows]
write("clean_xyzijk_inch.txt", "XYZIJK    INCH\n" + "\n".join(lines) + "\n")
# 9. tab-separated
write("clean_tab.tsv", table(H, canon, "\t"))
# 10. runs of spaces, aligned columns, unit in brackets split by a space
widths = [4, 7, 12, 12, 10, 13, 13, 13, 10]
fmt = lambda fields: "  ".join(f.rjust(w) for f, w in zip(fields, widths)).rstrip()
head = ["id", "curve", "x", "y", "z", "nx", "ny", "nz", "dev"]
write("clean_spaces.txt", fmt(head[:8] + ["dev (mm)"]) + "\n" + "".join(fmt(l) + "\n" for l in canon))
# 11. Windows-1252, German headers, decimal comma, deviation in um (micro sign = byte 0xB5)
lines = [[l[0], l[1]] + [comma(f) for f in l[2:8]] + [comma(um(l[8]))] for l in canon]
write(
    "clean_windows1252_german.csv",
    table(["Punkt", "Kurve", "Soll X", "Soll Y", "Soll Z", "Vektor I", "Vektor J", "Vektor K", "Abw. [µm]"], lines, ";"),
    encoding="cp1252",
)
# 12. UTF-8 with BOM, CRLF line ends
write("clean_bom_crlf.csv", "\ufeff" + table(H, canon, ",").replace("\n", "\r\n"))
# 13. positions in inches (header unit), deviation in mm
lines = [[l[0], l[1]] + [inch(f) for f in l[2:5]] + l[5:] for l in canon]
write("clean_inch_header.csv", table(["id", "curve", "x [in]", "y [in]", "z [in]", "nx", "ny", "nz", "deviation [mm]"], lines, ","))
print("wrote", len(list(OUT.iterdir())), "files to", OUT)
