"""The comparison script of issue 21: a NumPy/SciPy identification of a CMM file (the 100
built-in points, canonical columns) against the Figure-19 sensitivity matrix of the reference
(tests/data/reference/sensitivity_physical.csv, mm of defect per rad or per mm). Least squares with
column scaling, std from the residual, JSON out: what a lab script does, without the diagnosis.
Usage: python scipy_identify.py CMM.csv SENSITIVITY.csv
"""
import csv
import json
import sys

import numpy as np
import scipy.linalg


def main(cmm_path, sens_path):
    with open(sens_path, newline="") as f:
        rows = list(csv.reader(f))
    names = rows[0][2:]
    design = {int(r[0]): [float(x) for x in r[2:]] for r in rows[1:]}
    with open(cmm_path, newline="") as f:
        rdr = csv.DictReader(f)
        pts = [(int(r["id"]), float(r["deviation"])) for r in rdr]
    a = np.array([design[i] for i, _ in pts])
    y = np.array([d for _, d in pts])
    scale = np.linalg.norm(a, axis=0)
    sol, _, rank, _ = scipy.linalg.lstsq(a / scale, y)
    beta = sol / scale
    r = y - a @ beta
    dof = max(len(y) - rank, 1)
    s2 = float(r @ r) / dof
    cov = s2 * np.linalg.pinv((a / scale).T @ (a / scale)) / np.outer(scale, scale)
    out = {n: {"value": float(b), "std": float(np.sqrt(c))} for n, b, c in zip(names, beta, np.diag(cov))}
    json.dump({"parameters": out, "rms": float(np.sqrt(np.mean(r * r)))}, sys.stdout)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
