//! The turn of velocity and acceleration spectra into displacement at the band lines, before
//! any cross-spectral sum, so that every estimator sees displacement ([`Response`]).

use crate::Choice;
use faer::c64;

use super::builder::Plan;
use crate::error::{Channel, Error};
use crate::records::{Record, Response};
use crate::spectra::Window;

/// Per line of `lines` (spacing `resolution_hz`), the factors $1/s^p$, $p = 0, 1, 2$, with
/// $s = \sigma + i\omega$ and $\sigma$ the exponential window's decay (0 for the others): the
/// conversion of velocity and acceleration spectra to displacement at the band lines, before any
/// cross-spectral sum, so that every estimator sees displacement (see [`Response`]).
pub(super) fn to_displacement(
    lines: &[usize],
    resolution_hz: f64,
    window: Window,
) -> Vec<[Option<c64>; 3]> {
    let sigma = window.decay_per_s().unwrap_or(0.0);
    lines
        .iter()
        .map(|&k| {
            let omega = 2.0 * std::f64::consts::PI * k as f64 * resolution_hz;
            std::array::from_fn(|p| Response::ALL[p].divisor(sigma, omega))
        })
        .collect()
}

/// [`Error::ResponseAtZeroFrequency`] for response channel `c` of `record` at line `l`.
pub(super) fn response_at_dc(record: &Record, plan: &Plan, c: usize, l: usize) -> Error {
    Error::ResponseAtZeroFrequency {
        record: record.label().to_owned(),
        channel: Channel::Displacement(c),
        response: record.response(c).name(),
        freq_hz: plan.lines[l] as f64 * plan.resolution_hz,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frf::Estimator;
    use crate::frf::builder::Plan;
    use crate::frf::contribution::contribute;
    use crate::spectra::{Segmentation, SpectralEstimator};

    #[test]
    fn conversion_divides_by_s_with_the_window_decay() {
        let window = Window::exponential(3.0).unwrap();
        let factors = to_displacement(&[2], 0.5, window);
        let s = c64::new(3.0, 2.0 * std::f64::consts::PI);
        let one = c64::new(1.0, 0.0);
        let [d, v, a] = factors[0].map(Option::unwrap);
        assert!((d - one).norm() < 1e-15);
        assert!((v * s - one).norm() < 1e-15);
        assert!((a * s * s - one).norm() < 1e-15);
        // No window: s = iω; DC has no conversion.
        let factors = to_displacement(&[0, 1], 1.0, Window::Rectangular);
        assert_eq!(factors[0][1], None);
        assert_eq!(factors[0][2], None);
        assert!(
            (factors[1][1].unwrap() * c64::new(0.0, 2.0 * std::f64::consts::PI) - one).norm()
                < 1e-15
        );
    }

    #[test]
    fn a_velocity_line_at_dc_is_a_typed_error() {
        let record = Record::new(
            "v",
            8.0,
            vec![vec![1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]],
            vec![vec![0.0; 8]],
        )
        .unwrap()
        .with_responses(vec![Response::Velocity])
        .unwrap();
        let mut spectral = SpectralEstimator::new(8, 8.0, Window::Rectangular).unwrap();
        let plan = Plan {
            n: 1,
            sample_rate: 8.0,
            len: 8,
            seg_len: 8,
            lines: vec![0, 1],
            resolution_hz: 1.0,
            to_displacement: to_displacement(&[0, 1], 1.0, Window::Rectangular),
            corrections: Vec::new(),
        };
        let e = contribute(
            Estimator::PairedSets,
            Segmentation::WholeRecord,
            &plan,
            &mut spectral,
            &record,
        )
        .unwrap_err();
        assert_eq!(
            e,
            Error::ResponseAtZeroFrequency {
                record: "v".into(),
                channel: Channel::Displacement(0),
                response: "velocity",
                freq_hz: 0.0
            }
        );
        assert_eq!(e.kind(), "bad_band");
    }
}
