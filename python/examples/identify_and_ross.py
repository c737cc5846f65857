"""Simulate the seed's rig, identify it, print the result, and run a ROSS modal analysis with
the identified bearing.

Run from a checkout:  pip install ./python && python python/examples/identify_and_ross.py
(the ROSS part runs when ROSS 3.x is importable: pip install ross-rotordynamics, Python >= 3.13)
"""

import numpy as np

import bearing_ident as bi

# 8 hammer hits per direction on the 2-DOF rig of Diaz & San Andres (1999), 5 % noise floor.
records = bi.simulate("impact", impacts=8, noise=0.05, seed=1)
result = bi.identify(records, band=(8.0, 49.0), method="ivf")

truth = {"K": np.array([[146.3e3, 22.3e3], [11.5e3, 169.1e3]]), "M": np.diag([4.7, 4.8])}
print(result)
for name in ("K", "C", "M"):
    value, std = getattr(result, name), getattr(result, name + "_std")
    fmt = {"float_kind": lambda v: f"{v:.4g}"}
    print(f"{name} =\n{np.array2string(value, formatter=fmt)}\n  ± {np.array2string(std, formatter=fmt)}")
print("K error vs truth (relative):", np.abs(result.K - truth["K"]).max() / np.abs(truth["K"]).max())
print("natural frequencies (Hz):", np.round(result.natural_frequencies_hz, 3))
print("damping ratios:", np.round(result.damping_ratios, 4))
for kind, message in result.warnings:
    print("warning:", kind, message)

try:
    import ross as rs
except ImportError:
    print("ROSS is not importable here (it needs Python >= 3.13): skipping the rotor model.")
    raise SystemExit(0)

# A steel shaft on two identified bearings: the rotor's damped modes at 3000 rpm.
steel = rs.Material(name="steel", rho=7810, E=211e9, G_s=81.2e9)
shaft = [rs.ShaftElement(L=0.25, idl=0.0, odl=0.05, material=steel) for _ in range(6)]
disk = rs.DiskElement.from_geometry(n=3, material=steel, width=0.07, i_d=0.05, o_d=0.28)
bearings = [result.to_ross(n=0, tag="brg0"), result.to_ross(n=6, tag="brg6")]
rotor = rs.Rotor(shaft, [disk], bearings)
modal = rotor.run_modal(speed=3000 * np.pi / 30)
print("rotor damped natural frequencies at 3000 rpm (Hz):", np.round(modal.wd[:4] / (2 * np.pi), 2))
