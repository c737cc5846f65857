//! Units of Universal File time histories: the units label of the ordinate (record 9) read
//! and converted to SI, as pyuff writes it; a label the crate does not know is a warning, the
//! values used as read; a unit of another quantity, or a given one not known, an error.

use bearing_ident::Warning;
use bearing_ident::uff::{self, UffLayout};
use bearing_ident::units::{INCH, LBF};

/// Three time histories as pyuff 2.5.8 writes them (`prepare_58` with
/// `ordinate_axis_units_lab` `lbf`, `mil`, `V`; exponents 0/1, 1/0, 0/0; trailing spaces
/// removed): a force at 1+X, a probe at 1+X and a sensor at 2+X in volts.
const PYUFF: &str = "\
    -1
    58
lbf
NONE
NONE
NONE
NONE
    1         0    0         0          x         1   1          x         0   0
         4         8         1  0.00000e+00  1.00000e-03  0.00000e+00
        17    0    0    0 NONE                 s
        13    0    1    0 NONE                 lbf
         0    0    0    0 NONE                 NONE
         0    0    0    0 NONE                 NONE
  -2.00000000000e+00  -1.00000000000e+00   0.00000000000e+00   1.00000000000e+00
   2.00000000000e+00   3.00000000000e+00   4.00000000000e+00   5.00000000000e+00
    -1
    -1
    58
mil
NONE
NONE
NONE
NONE
    1         0    0         0          x         1   1          x         0   0
         4         8         1  0.00000e+00  1.00000e-03  0.00000e+00
        17    0    0    0 NONE                 s
         8    1    0    0 NONE                 mil
         0    0    0    0 NONE                 NONE
         0    0    0    0 NONE                 NONE
   0.00000000000e+00   5.00000000000e-01   1.00000000000e+00   1.50000000000e+00
   2.00000000000e+00   2.50000000000e+00   3.00000000000e+00   3.50000000000e+00
    -1
    -1
    58
V
NONE
NONE
NONE
NONE
    1         0    0         0          x         2   1          x         0   0
         4         8         1  0.00000e+00  1.00000e-03  0.00000e+00
        17    0    0    0 NONE                 s
         8    0    0    0 NONE                 V
         0    0    0    0 NONE                 NONE
         0    0    0    0 NONE                 NONE
   0.00000000000e+00   1.00000000000e+00   2.00000000000e+00   3.00000000000e+00
   4.00000000000e+00   5.00000000000e+00   6.00000000000e+00   7.00000000000e+00
    -1
";

fn layout(force: &str, response: &str) -> UffLayout {
    UffLayout {
        forces: vec![force.parse().unwrap()],
        responses: vec![response.parse().unwrap()],
        ..UffLayout::default()
    }
}

#[test]
fn units_labels_convert_to_si_and_unknown_ones_warn() {
    let functions = uff::parse(PYUFF.as_bytes(), "pyuff.uff").unwrap();
    assert_eq!(functions.len(), 3);
    // lbf and mil: converted on reading, each sample the number times its unit.
    let r = &uff::records_with(&functions, "pyuff.uff", &layout("id:lbf", "id:mil")).unwrap()[0];
    for k in 0..8 {
        let (f, x) = (k as f64 - 2.0, 0.5 * k as f64);
        assert_eq!(r.force(0)[k].to_bits(), (f * LBF).to_bits(), "sample {k}");
        assert_eq!(
            r.displacement(0)[k].to_bits(),
            (x * (1e-3 * INCH)).to_bits()
        );
    }
    assert!(r.warnings().is_empty());
    // V: not a unit the crate converts: read as SI, and a warning names file, channel, unit.
    let r = &uff::records_with(&functions, "pyuff.uff", &layout("id:lbf", "id:V")).unwrap()[0];
    assert_eq!(r.displacement(0)[7].to_bits(), 7f64.to_bits());
    assert_eq!(
        r.warnings(),
        [Warning::UnknownUnit {
            record: "pyuff.uff".into(),
            channel: "2+X".into(),
            unit: "V".into(),
            force: false,
        }]
    );
    // Given units stand in for the labels.
    let given = UffLayout {
        force_units: vec!["N".into()],
        response_units: vec!["mm".into()],
        ..layout("id:lbf", "id:V")
    };
    let r = &uff::records_with(&functions, "pyuff.uff", &given).unwrap()[0];
    assert_eq!(r.force(0)[0].to_bits(), (-2f64).to_bits());
    assert_eq!(r.displacement(0)[7].to_bits(), (7.0 * 1e-3f64).to_bits());
    assert!(r.warnings().is_empty());
    // A length on a force channel, a given unit nobody knows, too many given units: errors
    // naming the file.
    let furlong = UffLayout {
        response_units: vec!["furlong".into()],
        ..layout("id:lbf", "id:mil")
    };
    let three = UffLayout {
        force_units: vec!["N".into(), "N".into(), "N".into()],
        ..layout("id:lbf", "id:mil")
    };
    for (layout, named) in [
        (layout("id:mil", "id:V"), "unit `mil`, not a force unit"),
        (furlong, "unit `furlong`, not a response unit"),
        (three, "names 3 units for 1 channels"),
    ] {
        let e = uff::records_with(&functions, "pyuff.uff", &layout).unwrap_err();
        assert!(e.to_string().contains("pyuff.uff"), "{e}");
        assert!(e.to_string().contains(named), "{e}");
    }
}
