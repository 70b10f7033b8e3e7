//! Laws of prepared shapes on disk (`localizer/persist.rs`): a loaded localizer answers
//! bit for bit as the fresh one, save -> load -> save reproduces the bytes, and stale,
//! truncated, corrupted, foreign and garbage files are clear errors, never a panic.

use dualspectra::evaluation::synthetic::{synthetic_pair, SyntheticPair, SyntheticParams};
use dualspectra::lab::persist::{crc32, FORMAT_VERSION, MAGIC};
use dualspectra::localizer::HostNumbering;
use dualspectra::{Error, Localization, Localizer, Options, Progress, Scale};
use std::path::PathBuf;
use std::sync::OnceLock;

/// Light settings; resolution 300 < 642 vertices, so the decimated path (transferred
/// scale-invariant factor, keypoint descriptors) is what is stored.
fn light() -> Options {
    Options { k: 6, max_iterations: 8, plane_cuts: 2, resolution: 300, threads: 2, ..Options::default() }
}

fn pair() -> &'static SyntheticPair {
    static PAIR: OnceLock<SyntheticPair> = OnceLock::new();
    PAIR.get_or_init(|| synthetic_pair(&SyntheticParams { level: 3, ..SyntheticParams::default() }).unwrap())
}

fn prepared() -> &'static (Localizer, Vec<u8>) {
    static PREPARED: OnceLock<(Localizer, Vec<u8>)> = OnceLock::new();
    PREPARED.get_or_init(|| {
        let localizer = Localizer::new(&pair().full, &light()).unwrap();
        let bytes = localizer.to_bytes();
        (localizer, bytes)
    })
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dualspectra_persist_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Every number of two localizations, compared by their bits (timings aside).
fn assert_identical(a: &Localization, b: &Localization) {
    assert_eq!(a.region, b.region);
    assert_eq!(bits(&a.score), bits(&b.score));
    assert_eq!(bits(&a.potential), bits(&b.potential));
    assert_eq!(bits(&a.eigenvalues_regular), bits(&b.eigenvalues_regular));
    assert_eq!(bits(&a.eigenvalues_si), bits(&b.eigenvalues_si));
    assert_eq!(bits(&a.target_regular), bits(&b.target_regular));
    assert_eq!(bits(&a.target_si), bits(&b.target_si));
    assert_eq!((a.cost.to_bits(), a.confidence.to_bits()), (b.cost.to_bits(), b.confidence.to_bits()));
    assert_eq!((a.selected_start, a.n_starts), (b.selected_start, b.n_starts));
    assert_eq!(a.candidates.len(), b.candidates.len());
    for (x, y) in a.candidates.iter().zip(&b.candidates) {
        assert_eq!((&x.label, x.cost.to_bits(), x.iterations, &x.region), (&y.label, y.cost.to_bits(), y.iterations, &y.region));
        let s = |c: &dualspectra::Candidate| {
            [c.scores.region_cost, c.scores.descriptor_score, c.scores.partial_fit, c.scores.boundary_misfit, c.scores.vote_share].map(|v| v.map(f64::to_bits))
        };
        assert_eq!(s(x), s(y), "{}", x.label);
    }
    assert_eq!(a.warnings, b.warnings);
}

/// The error of loading `bytes` from a file, as text (it must name the file).
fn load_error(name: &str, bytes: &[u8]) -> String {
    let path = tmp(name);
    std::fs::write(&path, bytes).unwrap();
    let err = Localizer::load(&path).unwrap_err();
    assert!(matches!(err, Error::PreparedShape { .. }), "{err:?}");
    let text = err.to_string();
    assert!(text.contains(&path.display().to_string()), "{text} does not name the file");
    text
}

/// `bytes` with its payload replaced by `payload` and the header's length and checksum set to it.
fn with_payload(bytes: &[u8], payload: &[u8]) -> Vec<u8> {
    let header = header_length(bytes);
    let mut out = bytes[..header - 12].to_vec();
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&crc32(payload).to_le_bytes());
    out.extend_from_slice(payload);
    out
}

/// Bytes before the payload: magic, version, library version string, length, checksum.
fn header_length(bytes: &[u8]) -> usize {
    let n = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    16 + n + 12
}

#[test]
fn a_loaded_localizer_answers_bit_for_bit_as_the_fresh_one() {
    let (fresh, bytes) = prepared();
    let loaded = Localizer::from_bytes(bytes).unwrap();
    assert_eq!(loaded.options(), fresh.options());
    assert_eq!((loaded.n_vertices(), loaded.optimisation_vertices()), (fresh.n_vertices(), fresh.optimisation_vertices()));
    assert!(loaded.optimisation_vertices() < loaded.n_vertices(), "the decimated path is tested");
    let a = fresh.locate(&pair().partial, &Progress::none()).unwrap();
    let b = loaded.locate(&pair().partial, &Progress::none()).unwrap();
    assert_identical(&a, &b);
    // Through a file too, and with no decimation (the optimisation mesh is the full one).
    let path = tmp("fresh.dsprep");
    fresh.save(&path).unwrap();
    assert_identical(&a, &Localizer::load(&path).unwrap().locate(&pair().partial, &Progress::none()).unwrap());
    let whole = Options { resolution: 0, ..light() };
    let fresh = Localizer::new(&pair().full, &whole).unwrap();
    let loaded = Localizer::from_bytes(&fresh.to_bytes()).unwrap();
    assert_identical(
        &fresh.locate(&pair().partial, &Progress::none()).unwrap(),
        &loaded.locate(&pair().partial, &Progress::none()).unwrap(),
    );
}

#[test]
fn save_load_save_gives_the_same_bytes() {
    let (_, bytes) = prepared();
    assert!(bytes.starts_with(&MAGIC));
    assert_eq!(u32::from_le_bytes(bytes[8..12].try_into().unwrap()), FORMAT_VERSION);
    let again = Localizer::from_bytes(bytes).unwrap().to_bytes();
    assert!(again == *bytes, "the bytes changed on a round trip");
    let path = tmp("round.dsprep");
    Localizer::from_bytes(bytes).unwrap().save(&path).unwrap();
    assert!(std::fs::read(&path).unwrap() == *bytes);
    // Other thread counts give the same answer and keep the prepared data.
    let mut loaded = Localizer::load(&path).unwrap();
    loaded.set_threads(1).unwrap();
    assert_eq!(loaded.options().threads, 1);
    assert!(loaded.set_threads(100_000).is_err());
    // The partial's units are not part of what was prepared: they can change after loading.
    loaded.set_scale(Scale::Auto).unwrap();
    assert_eq!(loaded.options().scale, Scale::Auto);
    assert!(loaded.set_scale(Scale::Factor(-1.0)).is_err());
    assert_eq!(loaded.options().scale, Scale::Auto, "a refused scale leaves the option as it was");
}

#[test]
fn the_host_numbering_is_kept_and_checked() {
    let (fresh, _) = prepared();
    let n = fresh.n_vertices();
    let mut with_host = Localizer::from_bytes(&fresh.to_bytes()).unwrap();
    assert!(with_host.host_numbering().is_none());
    // Host vertex 0 was dropped by the caller's intake; the rest shift by one.
    let host = HostNumbering { n_host_vertices: n + 1, kept: (1..=n as u32).collect() };
    with_host.set_host_numbering(Some(host.clone())).unwrap();
    let loaded = Localizer::from_bytes(&with_host.to_bytes()).unwrap();
    assert_eq!(loaded.host_numbering(), Some(&host));
    let mut region = vec![false; n];
    region[0] = true;
    let mapped = host.region_to_host(&region);
    assert_eq!((mapped.len(), mapped[0], mapped[1]), (n + 1, false, true));
    let bad = HostNumbering { n_host_vertices: n, kept: (1..=n as u32).collect() };
    assert!(with_host.set_host_numbering(Some(bad)).unwrap_err().to_string().contains("maps vertex"));
    let short = HostNumbering { n_host_vertices: n, kept: vec![0; n - 1] };
    assert!(with_host.set_host_numbering(Some(short)).is_err());
    // The mesh in the given units, to rounding.
    let back = fresh.full_mesh();
    for (p, q) in back.vertices().iter().zip(pair().full.vertices()) {
        for c in 0..3 {
            assert!((p[c] - q[c]).abs() <= 4.0 * f64::EPSILON * q[c].abs().max(1.0), "{p:?} vs {q:?}");
        }
    }
}

#[test]
fn a_stale_file_asks_to_prepare_again() {
    let (_, bytes) = prepared();
    let mut stale = bytes.clone();
    stale[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    let text = load_error("stale.dsprep", &stale);
    assert!(text.contains("stale") && text.contains(&format!("format version {}", FORMAT_VERSION + 1)) && text.contains("prepare the shape again"), "{text}");
    // Another library version with the same format loads, with a warning in every result.
    let mut other = bytes[..12].to_vec();
    other.extend_from_slice(&5u32.to_le_bytes());
    other.extend_from_slice(b"0.0.9");
    other.extend_from_slice(&bytes[header_length(bytes) - 12..]);
    let loaded = Localizer::from_bytes(&other).unwrap();
    assert!(loaded.warnings().iter().any(|w| w.contains("prepared by dualspectra 0.0.9")), "{:?}", loaded.warnings());
    assert!(Localizer::from_bytes(&loaded.to_bytes()).unwrap().warnings().is_empty(), "the note is not saved");
}

#[test]
fn truncated_and_corrupted_files_are_reported_as_such() {
    let (_, bytes) = prepared();
    let header = header_length(bytes);
    for cut in [0, 3, 8, 10, 14, header - 5, header, header + 7, bytes.len() / 2, bytes.len() - 1] {
        let text = load_error("cut.dsprep", &bytes[..cut]);
        let expected = if cut == 0 { "empty file" } else { "truncated" };
        assert!(text.contains(expected), "cut at {cut}: {text}");
    }
    let mut longer = bytes.clone();
    longer.extend_from_slice(b"tail");
    assert!(load_error("long.dsprep", &longer).contains("corrupted: 4 bytes after"));
    for at in [header, header + 100, bytes.len() / 2, bytes.len() - 1] {
        let mut flipped = bytes.clone();
        flipped[at] ^= 0x10;
        let text = load_error("flip.dsprep", &flipped);
        assert!(text.contains("corrupted: the checksum"), "byte {at}: {text}");
    }
}

#[test]
fn counts_are_checked_before_allocating_and_structure_after_the_checksum() {
    let (_, bytes) = prepared();
    let payload = &bytes[header_length(bytes)..];
    // The options string announces 4 GB: refused without allocating.
    let mut huge = payload.to_vec();
    huge[0..4].copy_from_slice(&u32::MAX.to_le_bytes());
    let text = load_error("huge.dsprep", &with_payload(bytes, &huge));
    assert!(text.contains("more bytes"), "{text}");
    // A payload cut short, with a checksum that matches: the structure check finds it.
    let text = load_error("short.dsprep", &with_payload(bytes, &payload[..payload.len() / 3]));
    assert!(text.contains("left") || text.contains("announced"), "{text}");
    // Options that are not valid.
    let mut options = payload.to_vec();
    let n = u32::from_le_bytes(options[0..4].try_into().unwrap()) as usize;
    let json = String::from_utf8(options[4..4 + n].to_vec()).unwrap().replace("\"k\":6", "\"k\":0");
    assert_eq!(json.len(), n);
    options[4..4 + n].copy_from_slice(json.as_bytes());
    let text = load_error("options.dsprep", &with_payload(bytes, &options));
    assert!(text.contains("options") && text.contains("k = 0"), "{text}");
}

#[test]
fn foreign_files_and_garbage_are_not_prepared_shapes() {
    let off = b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let text = load_error("mesh.dsprep", off);
    assert!(text.contains("not a dualspectra prepared shape") && text.contains("'OFF."), "{text}");
    // Pseudo-random garbage of many lengths, bare or behind the magic and the version.
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for len in [1usize, 7, 9, 16, 33, 100, 1000, 100_000] {
        let garbage: Vec<u8> = (0..len).map(|_| next() as u8).collect();
        let err = Localizer::from_bytes(&garbage).unwrap_err();
        assert!(matches!(err, Error::PreparedShape { .. }), "{err:?}");
        let mut behind = MAGIC.to_vec();
        behind.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        behind.extend_from_slice(&garbage);
        let err = Localizer::from_bytes(&behind).unwrap_err().to_string();
        assert!(err.contains("truncated") || err.contains("corrupted") || err.contains("UTF-8") || err.contains("more bytes"), "{len}: {err}");
    }
    let missing = Localizer::load(tmp("missing.dsprep")).unwrap_err();
    assert!(matches!(missing, Error::Io { .. }), "{missing:?}");
}
