use super::*;
use crate::io;
use crate::simulate::{AntiAlias, ImpactTest, Kind, Setup, Simulator, seed_rig};

/// `records` written as CSV files into `dir`, their paths in order.
fn write(dir: &Path, records: &[Record]) -> Vec<PathBuf> {
    records
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let path = dir.join(format!("r{i}.csv"));
            io::write_record(&path, r, &Channels::default().csv).unwrap();
            path
        })
        .collect()
}

fn impacts() -> Vec<Record> {
    let test = ImpactTest {
        per_direction: 2,
        noise: 0.02,
        ..ImpactTest::seed_rig()
    };
    test.run(&seed_rig()).unwrap()
}

/// From files, the result is bit for bit that of the records read back and identified with
/// the settings the job reports; the files are named in the order given.
#[test]
fn files_are_identified_as_records_in_the_order_given() {
    let dir = tempfile::tempdir().unwrap();
    let mut paths = write(dir.path(), &impacts());
    paths.reverse();
    let job = Job::new(Options::new(8.0, 49.0), Channels::default());
    let outcome = job.run_files(&paths).unwrap();
    let labels: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    assert_eq!(outcome.files(), labels);
    assert_eq!(outcome.excitation(), Excitation::Impact);
    assert!(outcome.excitation_detected());
    let read: Vec<Record> = paths
        .iter()
        .map(|p| read_first(p, &Channels::default()).unwrap())
        .collect();
    let direct = outcome.identifier().identify(&read).unwrap();
    assert_eq!(
        outcome.identification().coefficients(),
        direct.coefficients()
    );
    let in_memory = job.run_records(read).unwrap();
    assert_eq!(
        in_memory.identification().coefficients(),
        direct.coefficients()
    );
    assert_eq!(in_memory.read_time(), Duration::ZERO);
}

/// Random records: the Welch length is chosen from a first fit and every file is kept, in
/// order, from files as from memory.
#[test]
fn random_files_choose_the_welch_length_and_keep_every_record() {
    let mut sim = Simulator::new(&seed_rig(), 256.0, 8192, AntiAlias::default()).unwrap();
    let records: Vec<Record> = (0..5)
        .map(|s| sim.random_record(format!("r{s}"), 50.0, s).unwrap())
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let paths = write(dir.path(), &records);
    let job = Job::new(Options::new(8.0, 49.0), Channels::default());
    let outcome = job.run_files(&paths).unwrap();
    assert_eq!(outcome.files().len(), 5);
    assert_eq!(outcome.files()[3], paths[3].display().to_string());
    assert_eq!(outcome.excitation(), Excitation::Random);
    let choice = outcome.welch_choice().expect("chosen from a first fit");
    assert_eq!(outcome.segment_len(), Some(choice.nperseg));
    let from_memory = job.run_records(records).unwrap();
    assert_eq!(from_memory.segment_len(), outcome.segment_len());
    let k = outcome.identification().coefficients().stiffness()[(0, 0)];
    let k_mem = from_memory.identification().coefficients().stiffness()[(0, 0)];
    assert!((k / k_mem - 1.0).abs() < 1e-9, "{k} vs {k_mem}");
    assert!((k / 146.3e3 - 1.0).abs() < 0.02, "{k}");
}

/// Random records, `noise` on every channel, `n` of `len` samples at `rate`.
fn noisy_random(rate: f64, len: usize, n: u64, noise: f64) -> Vec<Record> {
    use rand::SeedableRng;
    let mut sim = Simulator::new(&seed_rig(), rate, len, AntiAlias::default()).unwrap();
    let mut rng = rand::rngs::StdRng::seed_from_u64(9);
    (0..n)
        .map(|s| {
            let clean = sim.random_record(format!("r{s}"), 50.0, s).unwrap();
            crate::simulate::add_noise(&clean, noise, &mut rng).unwrap()
        })
        .collect()
}

/// Random records: the job's result is bit for bit that of [`Identifier::identify`] with the
/// settings it reports, whether the Welch choice keeps the default length (the identification
/// then finishes on the first fit's spectra) or a longer one; the choice is that of
/// [`crate::excitation::choose_welch`] by IVF; the stages add up to the total, the screening
/// among them.
#[test]
fn random_records_are_identified_as_the_settings_reported() {
    use crate::excitation::{choose_welch, welch_len};
    // Two records of 32 s at 256 S/s, 10 % noise, keep the default (1024 samples: 30
    // averages, twice as long would leave 14); two of 6 s at 6700 S/s, 2 % noise, want 8
    // lines in the rig's 4.4 Hz bandwidth, more than the default's 1.6 Hz spacing gives, and
    // get the longest that 16 averages allow.
    for (rate, len, noise, kept) in [(256.0, 8192, 0.1, true), (6700.0, 40_000, 0.02, false)] {
        let records = noisy_random(rate, len, 2, noise);
        let job = Job::new(Options::new(8.0, 49.0), Channels::default());
        let outcome = job.run_records(records.clone()).unwrap();
        let choice = outcome.welch_choice().expect("chosen from a first fit");
        assert_eq!(choice.nperseg == welch_len(len), kept, "{choice:?}");
        let direct = outcome.identifier().identify(&records).unwrap();
        assert_eq!(outcome.identification(), &direct, "{rate}");
        let (first, _) = job.identifier(Excitation::Random, &records[0]).unwrap();
        let by_ivf = first.method(Method::Ivf);
        assert_eq!(choose_welch(&records, &by_ivf).unwrap(), *choice);
        let t = outcome.timings();
        let parts: Duration = t.stages().iter().map(|(_, d)| *d).sum();
        assert!(parts <= t.total(), "{t:?}");
        assert!(t.welch_choice > Duration::ZERO && t.detect > Duration::ZERO);
        assert!(t.identification.spectra > Duration::ZERO);
        // The records are screened once, for the first fit: counted as the screen stage
        // whichever length the identification takes.
        assert!(t.identification.screen > Duration::ZERO, "{t:?}");
    }
}

/// Every piece of a run's work is in a named stage: the stages add up to at least 95 % of
/// the total (the rest is the bookkeeping between them), for impact records and for random
/// records whose Welch length is chosen from a first fit, in memory and from files. The
/// best of five runs is taken, so that the machine preempting the run between two stages
/// does not count as work outside them.
#[test]
fn stages_add_up_to_the_total() {
    let dir = tempfile::tempdir().unwrap();
    let random = noisy_random(6700.0, 40_000, 2, 0.02);
    let paths = write(dir.path(), &random);
    let job = Job::new(Options::new(5.0, 60.0), Channels::default());
    let runs: [(&str, &dyn Fn() -> Outcome); 3] = [
        ("impacts", &|| job.run_records(impacts()).unwrap()),
        ("random", &|| job.run_records(random.clone()).unwrap()),
        ("random files", &|| job.run_files(&paths).unwrap()),
    ];
    for (name, run) in runs {
        let covered = (0..5)
            .map(|_| {
                let t = run().timings();
                let parts: Duration = t.stages().iter().map(|(_, d)| *d).sum();
                assert!(parts <= t.total(), "{name}: {t:?}");
                parts.as_secs_f64() / t.total().as_secs_f64()
            })
            .fold(0.0, f64::max);
        assert!(
            covered >= 0.95,
            "{name}: the stages cover {covered:.3} of the total"
        );
    }
}

/// Sweep and stepped-sine files (the `simulate` command's defaults, 2 % noise) identified in
/// the band 8–49 Hz with the excitation left to detection: read as what they are (the first
/// file decides, the others streamed or, for stepped sine, gathered), identified exactly as
/// with the excitation given, and the seed rig's stiffness within three standard deviations.
#[test]
fn sweep_and_stepped_sine_files_are_detected_and_identified_as_when_given() {
    let truth = seed_rig();
    for (kind, excitation) in [
        (Kind::Sweep, Excitation::Sweep),
        (Kind::SteppedSine, Excitation::SteppedSine),
    ] {
        let setup = Setup {
            kind,
            noise: 0.02,
            ..Setup::default()
        };
        let records = setup.run(&truth).unwrap().records;
        let dir = tempfile::tempdir().unwrap();
        let paths = write(dir.path(), &records);
        let auto = Job::new(Options::new(8.0, 49.0), Channels::default())
            .run_files(&paths)
            .unwrap();
        assert_eq!(auto.excitation(), excitation);
        assert!(auto.excitation_detected());
        assert_eq!(auto.files().len(), records.len());
        let mut options = Options::new(8.0, 49.0);
        options.excitation = Some(excitation);
        let given = Job::new(options, Channels::default())
            .run_files(&paths)
            .unwrap();
        assert!(!given.excitation_detected());
        let (a, g) = (auto.identification(), given.identification());
        assert_eq!(a.coefficients(), g.coefficients(), "{excitation}");
        assert_eq!(a.std_dev(), g.std_dev(), "{excitation}");
        let k = a.coefficients().stiffness();
        let sd = a.std_dev().expect("error bars").stiffness();
        for i in 0..2 {
            for j in 0..2 {
                let off = (k[(i, j)] - truth.stiffness()[(i, j)]).abs();
                assert!(
                    off <= 3.0 * sd[(i, j)],
                    "{excitation} K[{i}][{j}] = {} ± {}, truth {}",
                    k[(i, j)],
                    sd[(i, j)],
                    truth.stiffness()[(i, j)]
                );
            }
        }
    }
}

/// A force that reads as more than one kind stops the run before any fit, naming the kinds;
/// the excitation given settles it.
#[test]
fn an_unclear_excitation_is_asked_for() {
    use rand::SeedableRng;
    let tone = crate::simulate::sine(12.5, std::f64::consts::SQRT_2, 1000.0, 8000).unwrap();
    let clean = Record::new("noisy-tone", 1000.0, vec![tone], vec![vec![1.0; 8000]]).unwrap();
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    let noisy = crate::simulate::add_noise(&clean, 0.73, &mut rng).unwrap();
    let job = Job::new(Options::new(8.0, 49.0), Channels::default());
    let e = job.run_records(vec![noisy.clone()]).unwrap_err();
    assert_eq!(e.kind(), "unclear_excitation");
    assert!(
        e.to_string()
            .contains("--excitation random|periodic|stepped-sine"),
        "{e}"
    );
    let mut options = Options::new(8.0, 49.0);
    options.excitation = Some(Excitation::Random);
    let job = Job::new(options, Channels::default());
    let (kind, _, detected) = job.excitation(&noisy, std::iter::empty()).unwrap();
    assert_eq!((kind, detected), (Excitation::Random, false));
}

/// A periodic test without a period given or found (impacts do not repeat) is refused,
/// naming the option; a band that does not
/// parse is `bad_band`.
#[test]
fn options_that_do_not_fit_are_named() {
    let mut options = Options::new(8.0, 49.0);
    options.excitation = Some(Excitation::Periodic);
    let e = Job::new(options.clone(), Channels::default())
        .run_records(impacts())
        .unwrap_err();
    assert!(
        matches!(
            e,
            Error::InvalidOption {
                option: "period",
                ..
            }
        ),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "--excitation periodic: the first record's force does not repeat within half its \
         length; give --period SECONDS"
    );
    options.period_s = Some(1e3);
    let e = Job::new(options, Channels::default())
        .run_records(impacts())
        .unwrap_err();
    assert!(e.to_string().starts_with("--period 1000: "), "{e}");
    assert!(matches!(
        Job::new(Options::new(8.0, 49.0), Channels::default()).run_files(&[]),
        Err(Error::NoRecords)
    ));
}

/// A baseline folder holding the system's own records leaves zero, with variances that add;
/// a baseline file that is not JSON is `bad_baseline` naming the file.
#[test]
fn baseline_folder_subtracts_and_a_bad_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let records = impacts();
    write(dir.path(), &records);
    let mut options = Options::new(8.0, 49.0);
    options.baseline = Some(dir.path().to_owned());
    let outcome = Job::new(options.clone(), Channels::default())
        .run_records(records.clone())
        .unwrap();
    let bearing = outcome.bearing().expect("a baseline");
    let k = outcome.identification().coefficients().stiffness()[(0, 0)];
    assert!(bearing.coefficients.stiffness()[(0, 0)].abs() < 1e-9 * k);
    let std = outcome.identification().std_dev().unwrap().stiffness()[(0, 0)];
    let both = bearing.std_dev.as_ref().unwrap().stiffness()[(0, 0)];
    assert!((both / (std * 2f64.sqrt()) - 1.0).abs() < 1e-9);
    if cfg!(not(feature = "json")) {
        return;
    }
    let bad = dir.path().join("r0.csv");
    options.baseline = Some(bad.clone());
    let e = Job::new(options, Channels::default())
        .run_records(records)
        .unwrap_err();
    assert_eq!(e.kind(), "bad_baseline");
    assert!(
        e.to_string()
            .starts_with(&format!("--baseline {}: ", bad.display()))
    );
}
