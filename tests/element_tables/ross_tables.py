"""Tables of a hole-pattern gas seal and of a magnetic bearing computed by ROSS, for
`tests/estimation/ross_elements.rs`.

Each table holds ROSS's coefficients of the element at the whirl frequencies 20, 40, ..., 1000 Hz,
one line per frequency: `frequency_hz`, then `k`, `c`, `m` for `xx, xy, yx, yy` (N/m, N s/m, kg),
the element's impedance being `H(w) = k(w) + i w c(w) - w^2 m(w)` as ROSS defines it.

- `hole_pattern_seal.csv`: `ross.seals.HolePatternSeal` with the parameters of its own docstring
  example (air, 145 mm shaft, 0.3 mm clearance, 47 mm long, 3.175 mm square cells 2.5 mm deep,
  689 kPa to 94.3 kPa at 322 K, preswirl 0.8, 8000 rpm), coefficients over the whirl-frequency
  grid (`frequency=`).
- `magnetic_bearing.csv`: `ross.MagneticBearingElement` with the actuator of ROSS's
  `rotor_example_amb_general_controllers` (138 turns, 470.3 mm^2 pole area, 0.432 mm gap, 1 A
  bias, pole angle 0.392 rad) under the controller `pid(k_p, k_i, k_d, n_f) * low_pass_filter(w_c)`
  of `ross.bearings.magnetic.amb_controllers`; ROSS returns `k = k_s + k_i Re G(iw)`,
  `c = k_i Im G(iw) / w`.

Regenerate (ROSS 3.1.0; run it from any folder not named `ross`):

    python3.13 -m venv /tmp/rossvenv && /tmp/rossvenv/bin/pip install ross-rotordynamics==3.1.0
    /tmp/rossvenv/bin/python tests/element_tables/ross_tables.py
"""

import os
import warnings

import numpy as np

warnings.filterwarnings("ignore")  # ccp's REFPROP notice; ROSS's unit warnings

import ross  # noqa: E402
from ross.bearings.magnetic.amb_controllers import combine, low_pass_filter, pid  # noqa: E402
from ross.seals.holepattern_seal import HolePatternSeal  # noqa: E402
from ross.units import Q_  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
FREQUENCY_HZ = np.arange(20.0, 1000.0 + 1e-9, 20.0)
OMEGA = 2.0 * np.pi * FREQUENCY_HZ

# The magnetic bearing's controller (gains in A/m, A/(m s), A s/m with unit sensor and amplifier
# gains, as ROSS's examples), derivative filter and low-pass corner in rad/s.
AMB_CONTROLLER = dict(k_p=4000.0, k_i=0.0, k_d=4.0, n_f=2.0 * np.pi * 600.0)
AMB_LOWPASS_RAD_S = 2.0 * np.pi * 400.0

PAIRS = ("xx", "xy", "yx", "yy")
HEADER = ",".join(
    ["frequency_hz"] + [f"{kind}{pair}" for kind in "kcm" for pair in PAIRS]
)


def row_values(element, kind, pair):
    values = np.asarray(getattr(element, f"{kind}{pair}"), dtype=float).ravel()
    if values.size == 1:
        values = np.full(FREQUENCY_HZ.size, values[0])
    return values


def write(name, element, note):
    columns = [FREQUENCY_HZ]
    for kind in "kcm":
        for pair in PAIRS:
            columns.append(
                row_values(element, kind, pair)
                if hasattr(element, f"{kind}{pair}")
                else np.zeros(FREQUENCY_HZ.size)
            )
    table = np.column_stack(columns)
    if not np.all(np.isfinite(table)):
        raise SystemExit(f"{name}: ROSS returned non-finite coefficients")
    path = os.path.join(HERE, name)
    with open(path, "w") as out:
        out.write(f"# {note}\n")
        out.write(HEADER + "\n")
        for row in table:
            out.write(",".join(f"{v:.7g}" for v in row) + "\n")
    print(f"wrote {path}")


def main():
    seal = HolePatternSeal(
        n=0,
        shaft_diameter=0.145,
        radial_clearance=0.0003,
        axial_length=0.04699,
        relative_roughness=0.0001,
        cell_length=0.003175,
        cell_width=0.003175,
        cell_depth=0.0025,
        inlet_pressure=689000.0,
        outlet_pressure=94300.0,
        inlet_temperature=322.0,
        speed=Q_([8000], "RPM"),
        frequency=OMEGA,
        gas_composition={"Nitrogen": 0.79, "Oxygen": 0.21},
        preswirl=0.8,
        entrance_loss_coefficient=0.5,
        exit_loss_coefficient=1.0,
        nz=18,
    )
    write(
        "hole_pattern_seal.csv",
        seal,
        f"ROSS {ross.__version__} HolePatternSeal, docstring example, 8000 rpm; "
        "regenerate with ross_tables.py",
    )

    controller = combine(pid(**AMB_CONTROLLER), low_pass_filter(AMB_LOWPASS_RAD_S))
    bearing = ross.MagneticBearingElement(
        n=0,
        g0=0.432e-3,
        i0=1.0,
        ag=470.3e-6,
        nw=138,
        alpha=0.392,
        controller_transfer_function=controller,
        frequency=list(OMEGA),
    )
    write(
        "magnetic_bearing.csv",
        bearing,
        f"ROSS {ross.__version__} MagneticBearingElement, k_s = {bearing.ks:.6g} N/m, "
        f"k_i = {bearing.ki:.6g} N/A, pid({AMB_CONTROLLER['k_p']:g}, "
        f"{AMB_CONTROLLER['k_i']:g}, {AMB_CONTROLLER['k_d']:g}, "
        f"n_f={AMB_CONTROLLER['n_f']:.6g}) * low_pass_filter({AMB_LOWPASS_RAD_S:.6g}); "
        "regenerate with ross_tables.py",
    )


if __name__ == "__main__":
    main()
