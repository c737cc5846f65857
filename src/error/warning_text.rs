//! The sentence of each [`Warning`]: what was seen, with its numbers.

use std::fmt;

use super::{NoiseBiasBasis, Warning};
use crate::Choice;
use crate::frf::Estimator;
use crate::text::significant;

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::IllConditioned {
                lines,
                of,
                worst_hz,
                worst,
                threshold,
            } => write!(
                f,
                "{lines} of {of} lines have a condition number above {threshold:.3e} \
                 (worst {worst:.3e} at {worst_hz:.3} Hz): excitations close to dependent"
            ),
            Warning::LowCoherence { lines, threshold } => write!(
                f,
                "{lines} lines dropped with a multiple coherence below {threshold}"
            ),
            Warning::InterferenceLine {
                freq_hz,
                channel,
                ratio,
                lines,
            } => write!(
                f,
                "{channel} has a line at {freq_hz} Hz {ratio:.0} times its neighbours with no \
                 response to match (interference such as mains hum): {lines} lines left out"
            ),
            Warning::JackknifeUnavailable { reason } => write!(
                f,
                "the jackknife cannot leave out a replicate that alone excites a direction (a \
                 refit without it: {reason}): sandwich standard deviations reported; give two \
                 or more records per direction for the jackknife"
            ),
            Warning::FewReplicates { replicates } => write!(
                f,
                "only {replicates} replicates for the jackknife (3 needed): sandwich standard deviations reported"
            ),
            Warning::DroppedLines { freqs_hz } => write!(
                f,
                "{} lines dropped (singular matrices) at {:?} Hz",
                freqs_hz.len(),
                freqs_hz
            ),
            Warning::UnpairedRecords { records } => write!(
                f,
                "{} records left out of the paired sets: {}",
                records.len(),
                records.join(", ")
            ),
            Warning::NotConverged { iterations, change } => write!(
                f,
                "not converged after {iterations} iterations (relative change {})",
                super::message::change_text(*change)
            ),
            Warning::Diverged {
                iterations,
                fallback_iteration,
            } => write!(
                f,
                "diverged after {iterations} iterations; returning iterate {fallback_iteration}"
            ),
            Warning::DoubleHit {
                record,
                second_s,
                ratio,
            } => write!(
                f,
                "record `{record}`: double hit, a second pulse at {second_s:.4} s of {ratio:.2} × the main peak"
            ),
            Warning::Clipped {
                record,
                channel,
                value,
            } => write!(f, "record `{record}`: {channel} clipped at {value:.4e}"),
            Warning::Rejected { record, reason } => {
                write!(f, "record `{record}` rejected: {reason}")
            }
            Warning::MlFellBack { reason } => {
                write!(f, "maximum likelihood kept the IVF result: {reason}")
            }
            Warning::MlWindowedRecords { decay_per_s } => write!(
                f,
                "maximum likelihood on whole records under an exponential window ({decay_per_s} 1/s): \
                 neighbouring lines correlate, so its error bars are too narrow (jackknife ones are safer)"
            ),
            Warning::PoorFit {
                row,
                col,
                r2,
                threshold,
            } => write!(
                f,
                "poor fit of flexibility element ({row},{col}): r² = {r2:.3} below {threshold}"
            ),
            Warning::NegativeDiagonal { block, dof, value } => write!(
                f,
                "{block}[{dof}][{dof}] = {value:.4e} is negative: not physical for a test system"
            ),
            Warning::UnstableMode {
                frequency_hz,
                damping_ratio,
            } => write!(
                f,
                "the fitted model is unstable: mode at {frequency_hz:.3} Hz with damping ratio {damping_ratio:.3}"
            ),
            Warning::DependentReplicates {
                replicates,
                distinct,
            } => write!(
                f,
                "only {distinct} of {replicates} replicates give distinct fits: records passed more than once? \
                 error bars understate the error"
            ),
            Warning::ZeroSpread { entries, of } => write!(
                f,
                "{entries} of {of} diagonal coefficients have zero resampled spread: the replicates are identical"
            ),
            Warning::WindowTooShort {
                decay_per_s,
                limit_per_s,
            } => write!(
                f,
                "exponential window decays at {decay_per_s:.4e} 1/s, faster than the lowest band frequency \
                 ({limit_per_s:.4e} rad/s): it leaves too little of the record"
            ),
            Warning::ForceGateShort {
                records,
                gate_s,
                pulse_end_s,
            } => write!(
                f,
                "force gate open {gate_s:.4e} s closes before the pulse ends (up to {pulse_end_s:.4} s) in {records} records"
            ),
            Warning::CoarseResolution {
                spacing_hz,
                mode_hz,
                half_power_hz,
                peak_bias,
            } => write!(
                f,
                "line spacing {spacing_hz:.4} Hz is coarse for the mode at {mode_hz:.3} Hz \
                 (half-power bandwidth {half_power_hz:.3} Hz): predicted peak bias {:.1} %",
                100.0 * peak_bias
            ),
            Warning::FewLines { lines, needed } => write!(
                f,
                "only {lines} lines in the band ({needed} wanted): little redundancy in the fit"
            ),
            // ---- Record screening ----
            Warning::UnknownUnit {
                record,
                channel,
                unit,
                force,
            } => {
                let (si, option) = if *force {
                    ("N", "--force-unit")
                } else {
                    ("m (m/s, m/s² for velocity, acceleration)", "--disp-unit")
                };
                write!(
                    f,
                    "record `{record}`: channel `{channel}` has unit `{unit}`, not one this \
                     crate converts: its samples were used as read, in {si}; give {option} to \
                     convert them"
                )
            }
            Warning::FlatChannel {
                record,
                channel,
                value,
            } => write!(
                f,
                "record `{record}`: {channel} is flat, every sample at {value:.4e} \
                 (a dead or disconnected sensor)"
            ),
            Warning::DeadChannel {
                record,
                channel,
                rms,
                median_rms,
            } => write!(
                f,
                "record `{record}`: {channel} is dead, RMS {rms:.3e} is {:.1e} × the median \
                 {median_rms:.3e} of its sibling records",
                rms / median_rms
            ),
            Warning::LevelOutlier {
                record,
                channel,
                rms,
                median_rms,
                sigmas,
            } => write!(
                f,
                "record `{record}`: {channel} level is an outlier, RMS {rms:.3e} is {:.3} × the \
                 median {median_rms:.3e} of its sibling records ({sigmas:.1} robust σ)",
                rms / median_rms
            ),
            Warning::DuplicateRecord { record, of } if record == of => write!(
                f,
                "record `{record}` passed again: the same samples as its first copy"
            ),
            Warning::DuplicateRecord { record, of } => write!(
                f,
                "record `{record}` holds the same samples as record `{of}` (the same data twice)"
            ),
            Warning::OutlierSet {
                records,
                far_lines,
                lines,
            } => write!(
                f,
                "paired set ({}): impedance far from the other sets' at {far_lines} of {lines} lines",
                records.join(", ")
            ),
            Warning::NonlinearMisfit {
                term,
                imaginary_ratio,
                slope,
            } => write!(
                f,
                "nonlinear term {term} does not fit: its coefficient spectrum has Im/Re = \
                 {imaginary_ratio:.3} and changes by {:.1} % across the band (a right regressor \
                 gives a real constant); its value is not the element's",
                100.0 * slope
            ),
            Warning::NegativeDissipation { term, value, std } => write!(
                f,
                "nonlinear term {term} is dissipative but came out negative ({value:.4e}{}): \
                 the element would feed energy into the motion, so the regressor is not the \
                 element's",
                std.map_or(String::new(), |s| format!(" ± {s:.2e}"))
            ),
            Warning::CollinearRegressors { term, coherence } => write!(
                f,
                "nonlinear term {term} is nearly collinear with the other inputs (multiple \
                 coherence {coherence:.4} on them): its coefficient is poorly determined"
            ),
            // ---- Field identification ----
            Warning::ModelResidual {
                speeds_rad_s,
                worst_ratio,
                limit,
            } => write!(
                f,
                "the rotor model leaves a residual above {limit} times what the stated response \
                 noise explains at {} speed(s) from {:.4} rad/s (worst {worst_ratio:.3e}): the \
                 rotor model, the probe positions or the responses' phase convention do not fit \
                 the measurements, and K, C there are not the bearings'",
                speeds_rad_s.len(),
                speeds_rad_s.first().copied().unwrap_or(f64::NAN)
            ),
            Warning::DependentTests { correlation } => write!(
                f,
                "the two tests' added imbalance forces are proportional (1 − correlation = \
                 {:.1e}): masses in one plane give a rank-1 pair of responses whatever their \
                 angles",
                1.0 - correlation
            ),
            Warning::SingularPair {
                bearing,
                speeds_rad_s,
                limit,
            } => write!(
                f,
                "bearing `{bearing}`: responses of the two tests dependent (condition number \
                 above {limit:.0e}) at {} speed(s) from {:.4} rad/s; K and C not given there",
                speeds_rad_s.len(),
                speeds_rad_s.first().copied().unwrap_or(f64::NAN)
            ),
            Warning::IllConditionedPair {
                bearing,
                speeds_rad_s,
                worst,
                threshold,
            } => write!(
                f,
                "bearing `{bearing}`: responses of the two tests nearly dependent (condition \
                 number above {threshold:.0e}, worst {worst:.3e}) at {} speed(s): near a \
                 critical speed one mode dominates every test's response; away from one, nearly \
                 circular orbits or nearly dependent tests; either way noise is amplified",
                speeds_rad_s.len()
            ),
            Warning::NotDecayed {
                remaining,
                block,
                row,
                col,
                relative,
                sigmas,
                window_end,
            } => write!(
                f,
                "the response has not decayed by the record's end ({:.2} % of the slowest \
                 mode's envelope left): truncation biases {block}[{row}][{col}] by {:+.2} % \
                 ({sigmas:.1} σ), carried in the error bars; an exponential window falling to {window_end:.1e} at the \
                 record's end (`--window exp:{window_end:.1e}`, corrected exactly) removes it",
                100.0 * remaining,
                100.0 * relative
            ),
            Warning::FrictionBias {
                term,
                predicted,
                random_std,
            } => write!(
                f,
                "nonlinear term {term}: velocity noise flips the sign of slow velocities, a \
                 predicted friction bias of up to {predicted:.3e} N{}, carried in its error bar; \
                 a less noisy velocity (a velocity probe, `--vel-cutoff`) reduces it",
                random_std.map_or(String::new(), |s| format!(" ({:.1} σ)", predicted / s))
            ),
            Warning::NoiseBias {
                estimator,
                basis,
                block,
                row,
                col,
                relative,
                sigmas,
            } => match basis {
                NoiseBiasBasis::Bracket => {
                    let other = match estimator {
                        Estimator::H2 => "H1",
                        _ => "H2",
                    };
                    write!(
                        f,
                        "{} and {other} on the same spectra differ by {:+.3} % on \
                         {block}[{row}][{col}] ({sigmas:.1} σ): noise on the force channels \
                         biases H1, on the responses H2, and the truth lies between; the \
                         difference is carried in the error bars (`--estimator hv` when both \
                         channels are about equally noisy)",
                        estimator.name().to_uppercase(),
                        100.0 * relative
                    )
                }
                NoiseBiasBasis::ForceSide => write!(
                    f,
                    "the segments show noise entering as the forces do: were it the force \
                     channels' measurement noise, H1 would be off by {:+.3} % on \
                     {block}[{row}][{col}] ({sigmas:.1} σ), were it an excitation they do not \
                     measure, H1 is exact; the difference is carried in the error bars \
                     (`--force-noise measurement` when the load cell is the noisy channel; \
                     repeated periods tell the two apart)",
                    -100.0 * relative
                ),
                NoiseBiasBasis::Compensation => write!(
                    f,
                    "H1 is compensated for the force measurement noise the records show; one \
                     standard error of that noise moves {block}[{row}][{col}] by {:+.3} % \
                     ({sigmas:.1} σ), carried in the error bars",
                    100.0 * relative
                ),
            },
            Warning::LeakageBias {
                spacing_hz,
                block,
                row,
                col,
                relative,
                sigmas,
            } => write!(
                f,
                "Welch segments with {spacing_hz:.4} Hz line spacing leak: predicted bias of \
                 {block}[{row}][{col}] {:+.2} % ({sigmas:.1} σ), carried in the error bars; \
                 longer segments (`--nperseg`) remove it",
                100.0 * relative
            ),
            Warning::PeriodMismatch {
                stated_s,
                suggested_s: Some(p),
            } => write!(
                f,
                "the stated period {stated_s} s does not fit the records (their force has \
                 energy between its harmonic lines); the data suggest {p:.6} s"
            ),
            Warning::PeriodMismatch {
                stated_s,
                suggested_s: None,
            } => write!(
                f,
                "the stated period {stated_s} s does not fit the records (their force has \
                 energy between its harmonic lines), and they show no period of their own"
            ),
            Warning::StartTransient {
                records,
                worst_ratio,
            } => write!(
                f,
                "the first period of {} record(s) (first `{}`) differs from the later ones \
                 {worst_ratio:.1} times more than their scatter: a start-up transient \
                 (leave it out with `--drop-periods 1`)",
                records.len(),
                records.first().map_or("", String::as_str)
            ),
            Warning::TransferFrf { dof, fraction } => write!(
                f,
                "G[{dof}][{dof}] has a positive imaginary part at {:.0} % of the lines: a \
                 transfer (non-drive-point) FRF, whose diagonal coefficients need not be \
                 positive (measure the response at the force for a drive point)",
                100.0 * fraction
            ),
            Warning::SwappedChannels { residual, original } => write!(
                f,
                "negative diagonal coefficients, while the data read the other way round \
                 (force as response, response as force) fit with every diagonal positive \
                 (relative residual {residual:.2e} against {original:.2e}): the force and \
                 response columns look exchanged; check `--force` and `--disp`"
            ),
            Warning::ResponseKind {
                suggested,
                residual,
                original,
            } => write!(
                f,
                "a negative diagonal mass from channels read as displacement; read as {suggested} they \
                 fit with every diagonal positive (relative residual {residual:.2e} against \
                 {original:.2e}): try `--response {suggested}`"
            ),
            Warning::MassSum {
                direction,
                sum_kg,
                std_kg,
                rotor_mass_kg,
            } => write!(
                f,
                "the bearings' added masses in {direction} sum to {} ± {} kg, {:.0} % of the \
                 rotor's modelled {} kg: the rotor model's mass is off by about that much, or \
                 the bearings carry that inertia (squeeze films, seals), or their stiffness \
                 changes with speed (the constant fit's M takes the trend)",
                significant(*sum_kg, 3),
                significant(*std_kg, 2),
                100.0 * sum_kg.abs() / rotor_mass_kg,
                significant(*rotor_mass_kg, 4)
            ),
            Warning::HighNoiseGain {
                bearing,
                speeds_rad_s,
                worst,
                threshold,
            } => write!(
                f,
                "bearing `{bearing}`: relative response noise is amplified more than \
                 {threshold:.0}-fold in Z at {} speed(s) from {:.4} rad/s (worst {worst:.0}): \
                 1 % noise gives errors of that many percent",
                speeds_rad_s.len(),
                speeds_rad_s.first().copied().unwrap_or(f64::NAN)
            ),
            Warning::NearPinnedCritical {
                speed_rad_s,
                critical_rad_s,
            } => write!(
                f,
                "speed {speed_rad_s:.4} rad/s is near {critical_rad_s:.4} rad/s, a critical \
                 speed of the rotor pinned at the probes: noise is amplified there"
            ),
            Warning::ModelMisfit {
                ratio,
                p_value,
                worst_hz,
                source,
            } => write!(
                f,
                "model misfit: the residual is {ratio:.3} times what the noise ({source}) \
                 explains (p = {p_value:.1e}), worst at {worst_hz:.4} Hz; the error bars carry \
                 it, but the coefficients may be biased: try a narrower band away from modes \
                 outside the model, more degrees of freedom, a residual or nonlinear term, or \
                 check the response kind (`--response`)"
            ),
            Warning::FrequencyDependent { family, poles_hz } => {
                let poles: Vec<String> = poles_hz.iter().map(|p| format!("{p:.3} Hz")).collect();
                let poles = match poles.is_empty() {
                    true => String::new(),
                    false => format!(" (poles at {})", poles.join(", ")),
                };
                write!(
                    f,
                    "the misfit is what a frequency-dependent element leaves: `{family}`{poles} \
                     fits within the noise; `--model auto` identifies it"
                )
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Channel;

    #[test]
    fn quality_warnings_name_the_record_and_numbers() {
        let w = Warning::DoubleHit {
            record: "hit-x-1".into(),
            second_s: 0.0512,
            ratio: 0.31,
        };
        assert_eq!(
            w.to_string(),
            "record `hit-x-1`: double hit, a second pulse at 0.0512 s of 0.31 × the main peak"
        );
        let w = Warning::Clipped {
            record: "hit-y-2".into(),
            channel: Channel::Displacement(1),
            value: -2.5e-4,
        };
        assert_eq!(
            w.to_string(),
            "record `hit-y-2`: displacement channel 1 clipped at -2.5000e-4"
        );
        let w = Warning::Rejected {
            record: "hit-y-3".into(),
            reason: "force channel 1 clipped".into(),
        };
        assert_eq!(
            w.to_string(),
            "record `hit-y-3` rejected: force channel 1 clipped"
        );
    }
}
