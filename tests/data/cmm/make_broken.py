#!/usr/bin/env python3
"""Writes tests/data/cmm/broken/: one file per error kind of shared/spec/cmm-csv.md (plus
truncated rows, mixed separators, wrong units, ...), each derived from example_clean.csv with
one defect at a known line. tests/it/cmm_broken.rs asserts the key words and line of each message.

Run from the repository root: python3 tests/data/cmm/make_broken.py
"""
import csv
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
OUT = ROOT / "tests/data/cmm/broken"
OUT.mkdir(exist_ok=True)
for old in OUT.iterdir():
    old.unlink()
SRC = ROOT / "tests/data/reference/examples/example_clean.csv"
lines = SRC.read_text().splitlines()  # lines[0] = header (file line 1), lines[k] = file line k+1
H = lines[0]


def write(name, text):
    data = text if isinstance(text, bytes) else text.encode("utf-8")
    (OUT / name).write_bytes(data)


def body(ls):
    return "\n".join(ls) + "\n"


def edit(line_no, column, value, src=None):
    """Copy of the file with field `column` (0-based) of file line `line_no` replaced."""
    ls = list(src or lines)
    f = ls[line_no - 1].split(",")
    f[column] = value
    ls[line_no - 1] = ",".join(f)
    return ls


def scale(factor, cols, header=H):
    out = [header]
    for l in lines[1:]:
        f = l.split(",")
        for c in cols:
            f[c] = repr(float(f[c]) * factor)
        out.append(",".join(f))
    return out


write("empty.csv", b"")
write("only_comments.csv", "# CMM export\n// nothing measured\n\n")
write("whitespace_only.csv", "   \n\t\n  \n")
write("header_only.csv", H + "\n")
write("binary_nul.csv", bytes(range(256)) * 4)
write("excel_xlsx_renamed.csv", b"PK\x03\x04\x14\x00\x06\x00\x08\x00\x00\x00!\x00" + bytes(200))
write("no_header.csv", body(lines[1:]))
write("unknown_header.csv", body(["foo,bar,baz,qux"] + lines[1:]))
write("missing_z.csv", body([",".join(l.split(",")[:4] + l.split(",")[5:]) for l in lines]))
write("missing_positions.csv", body([",".join(l.split(",")[:2] + l.split(",")[5:]) for l in lines]))
write("missing_normal_k.csv", body([",".join(l.split(",")[:7] + l.split(",")[8:]) for l in lines]))
write("not_numeric.csv", body(edit(5, 2, "abc")))
write("nan.csv", body(edit(7, 8, "NaN")))
write("infinite.csv", body(edit(9, 4, "inf")))
write("huge_number.csv", body(edit(10, 3, "1e400")))
write("empty_value.csv", body(edit(11, 6, "")))
write("truncated_last_row.csv", body(lines[:-1]) + lines[-1][:40])
write("truncated_middle_row.csv", body(lines[:30] + [",".join(lines[30].split(",")[:5])] + lines[31:]))
write("decimal_comma_in_comma_file.csv", body(edit(14, 8, lines[13].split(",")[8].replace(".", ","))))
write("mixed_separators.csv", body(lines[:19] + [lines[19].replace(",", ";")] + lines[20:]))
tab = [l.replace(",", "\t") for l in lines]
write("mixed_separators_tab_spaces.tsv", body(tab[:40] + [tab[40].replace("\t", "   ")] + tab[41:]))
write("duplicate_ids.csv", body(edit(12, 0, "5")))
write("too_few_points.csv", body(lines[:6]))
write("inch_without_unit.csv", body(scale(1 / 25.4, [2, 3, 4, 8])))
write("xyzijk_without_unit.txt", "XYZIJK\n" + body([",".join(l.split(",")[2:]) for l in lines[1:]]))
write("unknown_unit_header.csv", body([H.replace(",x,", ",x [ft],")] + lines[1:]))
write("micrometres_without_unit.csv", body(scale(1000, [8])))
write("mm_labelled_inch.csv", body(scale(1, [], H.replace(",x,y,z,", ",x [in],y [in],z [in],"))))
write("micrometre_positions_without_unit.csv", body(scale(1000, [2, 3, 4])))
shifted = [H] + [",".join([f[0], f[1], repr(float(f[2]) + 500)] + f[3:]) for f in (l.split(",") for l in lines[1:])]
write("misaligned.csv", body(shifted))
write("zero_normal.csv", body(edit(15, 5, "0", edit(15, 6, "0", edit(15, 7, "0")))))
write("duplicate_column.csv", body([H.replace("deviation", "X nom")] + lines[1:]))
write("single_implausible_deviation.csv", body(edit(25, 8, "5.250000")))
many = edit(33, 3, "12.3.4", edit(66, 0, "60"))
many = many[:79] + [",".join(many[79].split(",")[:6])] + many[80:]
write("several_bad_rows.csv", body(many))
pi = [" ".join(["P" + f[0]] + f[2:] + ["-0.05", "0.05"]) for f in (l.split(",") for l in lines[1:])]
write("powerinspect_truncated.txt", body(pi[:49] + [" ".join(pi[49].split()[:7])] + pi[50:]))
xy = [",".join(l.split(",")[2:]) for l in lines[1:]]
write("xyzijk_not_numeric.txt", "XYZIJK    METRIC\n" + body(xy[:9] + [xy[9].replace(xy[9].split(",")[2], "11.0x")] + xy[10:]))
write("utf16_binary_garbage.csv", b"\xff\xfe" + b"\x00\xd8" * 10)
write("control_characters.csv", (H + "\n").encode() + bytes([1, 2, 3, 4, 5, 6, 7, 8, 11, 14]) * 50)
q = [l + ",ok" for l in lines]
q[0] = H + ",comment"
q[7] = lines[7] + ',"probe slipped'
q[9] = lines[9] + ',see above"'
write("unbalanced_quote.csv", body(q))
far = list(lines)
f = far[29].split(",")
f[2] = repr(float(f[2]) + 3.0)
far[29] = ",".join(f)
write("point_far_from_surface.csv", body(far))
far = list(lines)
f = far[44].split(",")
for c in (2, 3, 4):
    f[c] = repr(float(f[c]) / 25.4)
far[44] = ",".join(f)
write("point_in_inches.csv", body(far))
print("wrote", len(list(OUT.iterdir())), "files to", OUT)
