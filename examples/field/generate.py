"""Writes ROTOR.json and the imbalance responses TESTS_bearings.json (probes at the bearings,
nodes 0 and 7) and TESTS_inboard.json (probes one node inboard, nodes 1 and 6) from a rotor
built with ROSS 3.1.0 (ross-rotordynamics, MIT licence): seven Timoshenko steel shaft elements
of 0.15 m and 60 mm, disks of 20 kg (node 2) and 15 kg (node 5), two cross-coupled bearings with
constant coefficients (below). The responses are ROSS's own `run_unbalance_response`, at
350–675 rad/s: baseline (residual 5e-5 kg·m at node 3, 0.7 rad), test 1 (+1e-4 kg·m at node 2,
0 rad), test 2 (+1e-4 kg·m at node 5, 1.5 rad). Run: python generate.py (outside any folder
named `ross`)."""
import json
import numpy as np
import ross as rs

steel = rs.materials.steel
shaft = [rs.ShaftElement(L=0.15, idl=0, odl=0.06, material=steel) for _ in range(7)]
disks = [rs.DiskElement(n=2, m=20.0, Id=0.13, Ip=0.25), rs.DiskElement(n=5, m=15.0, Id=0.1, Ip=0.2)]
bearings = {
    "brg0": dict(n=0, kxx=5e6, kxy=3e6, kyx=-3.6e6, kyy=2e7, cxx=5e3, cxy=500.0, cyx=-350.0, cyy=7.5e3),
    "brg1": dict(n=7, kxx=3.5e6, kxy=2.1e6, kyx=-2.52e6, kyy=1.4e7, cxx=3.5e3, cxy=500.0, cyx=-245.0, cyy=5.25e3),
}
rotor = rs.Rotor(shaft, disks, [rs.BearingElement(tag=t, **v) for t, v in bearings.items()])

to_list = lambda a: [[float(v) for v in row] for row in np.asarray(a)]
json.dump({"dof_per_node": 6, "dof_names": ["x", "y", "z", "alpha", "beta", "theta"],
           "M": to_list(rotor.M0), "K": to_list(rotor.K0), "G": to_list(rotor.G0),
           "C": to_list(rotor.C0),
           "bearings": [{"tag": b.tag, "node": b.n} for b in rotor.bearing_elements]},
          open("ROTOR.json", "w"))

speeds = np.arange(350.0, 680.0, 25.0)
runs = {"baseline": ([3], [5e-5], [0.7]),
        "1": ([3, 2], [5e-5, 1e-4], [0.7, 0.0]),
        "2": ([3, 5], [5e-5, 1e-4], [0.7, 1.5])}
responses = {name: np.asarray(rotor.run_unbalance_response(n, m, p, speeds).forced_resp)
             for name, (n, m, p) in runs.items()}
for label, nodes in (("bearings", (0, 7)), ("inboard", (1, 6))):
    out = []
    for name, fr in responses.items():
        for k, w in enumerate(speeds):
            for node in nodes:
                for d, dirn in ((0, "x"), (1, "y")):
                    q = fr[6 * node + d, k]
                    out.append({"speed_rad_s": float(w), "test": name, "node": node, "dir": dirn,
                                "re": float(q.real), "im": float(q.imag)})
    json.dump({"imbalances": {"1": [{"node": 2, "magnitude_kg_m": 1e-4, "phase_rad": 0.0}],
                              "2": [{"node": 5, "magnitude_kg_m": 1e-4, "phase_rad": 1.5}]},
               "responses": out}, open(f"TESTS_{label}.json", "w"))
