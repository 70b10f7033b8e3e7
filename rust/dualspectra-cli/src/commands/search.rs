//! `dualspectra search PARTIAL FULL... [--top N] [--json OUT] [--ply-dir DIR] [--png OUT]
//! [localize options]`
//!
//! Which of the full shapes is PARTIAL a part of, and where: the partial is located on each
//! (`dualspectra::search_with`) and the shapes are ranked by the similarity score
//! (`Localization::similarity_score`, lower is more similar; docs/algorithm.md,
//! "Searching several full shapes"). A FULL may be a mesh (.off, .obj, .ply: prepared
//! here with the options given), a prepared shape (.dsprep from `dualspectra prepare`:
//! loaded, with the options it was prepared with except `--scale` and `--threads`, which are
//! the search's), or a folder of these (its files, not its subfolders, by name). Prints a
//! table (rank, shape, score, region size, confidence) of the `--top N` best (default:
//! all); `--json` writes them with each region (0-based vertex indices of that FULL file),
//! `--ply-dir` each one's FULL with its region in red (`<rank>_<name>.ply`), `--png` a
//! picture of the ranking: the best shapes (at most [`PICTURE_SHAPES`]), each from the
//! front and the back with its region, labelled with rank, name and score; the ranking
//! rather than the best shape alone, so that the picture shows whether the best stands out
//! and where the part would sit on the runners-up. A progress bar runs over the shapes on
//! standard error.
//!
//! Shapes are opened (loaded or prepared) one at a time during the search and dropped after,
//! so memory holds one prepared shape plus the kept localizations; the ranked shapes are
//! opened again afterwards for what the output needs (a mesh file is read, not prepared).

use super::localize::{progress_bar, region_indices, write_region_ply, LocalizeOptions};
use super::prepare::{host_numbering, prepare_file};
use crate::error::CliError;
use crate::input::read_input_mesh;
use crate::output::{check_output_path, print_stdout, to_json_line, write_text};
use crate::render;
use dualspectra::localizer::EXTENSION;
use dualspectra::localizer::HostNumbering;
use dualspectra::search::SCREEN_EXTENSION;
use dualspectra::{Localizer, Match, Options, Progress, Screen, ScreenEntry, TriMesh};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// The partial shape (a deformed, cut copy of part of one of the FULL shapes).
    #[arg(value_name = "PARTIAL")]
    pub partial: PathBuf,
    /// Full shapes: meshes (.off, .obj, .ply), prepared shapes (.dsprep), or folders of them.
    #[arg(value_name = "FULL", num_args = 1.., required = true)]
    pub fulls: Vec<PathBuf>,
    /// Show, write and draw the N best shapes only (default: all).
    #[arg(long, value_name = "N")]
    pub top: Option<usize>,
    /// Write the ranking as JSON, with each shape's region.
    #[arg(long, value_name = "OUT")]
    pub json: Option<PathBuf>,
    /// Write each ranked FULL as PLY with its region in red, as DIR/<rank>_<name>.ply
    /// (DIR is created).
    #[arg(long, value_name = "DIR")]
    pub ply_dir: Option<PathBuf>,
    /// Write a PNG picture of the ranking: the best shapes (at most 6), each from the front
    /// and the back with its region in red, labelled with rank, name and score.
    #[arg(long, value_name = "OUT")]
    pub png: Option<PathBuf>,
    /// With more than N shapes, localize only the N that the screen ranks best (a few SHOT
    /// descriptors per shape; the others are listed as screened out). A number at least the
    /// shapes' count localizes every shape.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_SHORTLIST)]
    pub shortlist: usize,
    #[command(flatten)]
    pub options: LocalizeOptions,
    /// Drop vertices that belong to no face instead of failing.
    #[arg(long)]
    pub drop_isolated: bool,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// Shapes localized after the screen by default (docs/benchmarks/options.md, "Library
/// screen": the right class is among the screen's first 10 for most library queries).
pub const DEFAULT_SHORTLIST: usize = 10;

/// The screen of `paths` (meshes or prepared shapes), read one at a time.
pub fn describe_for_screen(paths: &[PathBuf], drop_isolated: bool, progress: &Progress) -> Result<Screen, CliError> {
    let mut entries = Vec::with_capacity(paths.len());
    for (i, path) in paths.iter().enumerate() {
        progress.report(i as f64 / paths.len() as f64, "describing the shapes")?;
        let mesh = if has_extension(path, EXTENSION) { Localizer::load(path)?.full_mesh() } else { read_input_mesh(path, drop_isolated)?.0 };
        entries.push(ScreenEntry::new(&mesh).map_err(|e| CliError::Core(e.in_file(path)))?);
    }
    Ok(Screen::new(&entries)?)
}

/// Shapes drawn by `--png` (the best ones): two rows of three.
pub const PICTURE_SHAPES: usize = 6;

/// Mesh and prepared-shape extensions a folder is searched for.
const EXTENSIONS: [&str; 4] = ["off", "obj", "ply", EXTENSION];

fn has_extension(path: &Path, wanted: &str) -> bool {
    path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case(wanted))
}

/// The FULL arguments with each folder replaced by its mesh and prepared-shape files, sorted.
pub fn expand_fulls(args: &[PathBuf]) -> Result<Vec<PathBuf>, CliError> {
    let mut out = Vec::new();
    for arg in args {
        if arg.is_dir() {
            let io = |source| CliError::Core(dualspectra::Error::Io { path: arg.clone(), source });
            let mut files: Vec<PathBuf> = std::fs::read_dir(arg)
                .map_err(io)?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && EXTENSIONS.iter().any(|x| has_extension(p, x)))
                .collect();
            if files.is_empty() {
                return Err(CliError::Usage(format!("{}: no .off, .obj, .ply or .{EXTENSION} file in this folder", arg.display())));
            }
            files.sort();
            out.extend(files);
        } else {
            out.push(arg.clone());
        }
    }
    Ok(out)
}

/// One full shape of the search: its file and name (the shape itself is open only while
/// it is searched).
struct Shape {
    path: PathBuf,
    name: String,
}

/// Load a `.dsprep` or read and prepare a mesh file.
fn open_full(path: &Path, options: &Options, threads: Option<usize>, drop_isolated: bool, progress: &Progress) -> Result<Localizer, CliError> {
    if has_extension(path, EXTENSION) {
        let mut localizer = Localizer::load(path)?;
        if let Some(t) = threads {
            localizer.set_threads(t)?;
        }
        // The partial's units are the search's, as the screen takes them.
        localizer.set_scale(options.scale)?;
        return Ok(localizer);
    }
    Ok(prepare_file(path, options, drop_isolated, progress)?.0)
}

/// What the output needs of a ranked shape, opened again after the search: the file's
/// numbering of its vertices (if reading changed it), its vertex count, and its mesh (for
/// `--ply-dir`).
struct Reopened {
    host: Option<HostNumbering>,
    n_vertices: usize,
    mesh: Option<TriMesh>,
}

/// Load a `.dsprep` again, or read a mesh file again (without preparing it).
fn reopen(path: &Path, drop_isolated: bool, with_mesh: bool) -> Result<Reopened, CliError> {
    if has_extension(path, EXTENSION) {
        let localizer = Localizer::load(path)?;
        let mesh = with_mesh.then(|| localizer.full_mesh());
        return Ok(Reopened { host: localizer.host_numbering().cloned(), n_vertices: localizer.n_vertices(), mesh });
    }
    let (mesh, report) = read_input_mesh(path, drop_isolated)?;
    Ok(Reopened { host: host_numbering(&mesh, &report), n_vertices: mesh.n_vertices(), mesh: with_mesh.then_some(mesh) })
}

impl Reopened {
    /// The region of a match in the file's numbering, and the file's vertex count.
    fn file_region(&self, region: &[bool]) -> (Vec<usize>, usize) {
        match &self.host {
            Some(h) => (region_indices(&h.region_to_host(region)), h.n_host_vertices),
            None => (region_indices(region), region.len()),
        }
    }

    /// The file's vertex count.
    fn file_vertices(&self) -> usize {
        self.host.as_ref().map_or(self.n_vertices, |h| h.n_host_vertices)
    }
}

/// One ranked shape in the JSON.
#[derive(Debug, Serialize)]
struct Ranked<'a> {
    rank: usize,
    shape: &'a Path,
    /// Lower is more similar; null when the partial could not be located on it.
    score: Option<f64>,
    /// Vertices of the region and of the shape, in the file's numbering.
    region_vertices: usize,
    n_vertices: usize,
    /// How much to trust that the partial is a part of this shape rather than of another one
    /// searched (the search's confidence, [0, 1]).
    confidence: Option<f64>,
    /// The localization's own confidence (that its region fits, whatever the other shapes).
    localization_confidence: Option<f64>,
    cost: Option<f64>,
    /// The region: 0-based vertex indices of the shape's file.
    region: Vec<usize>,
    error: Option<&'a str>,
    /// The screen's score (lower is more similar) when the search was screened.
    screen_score: Option<f64>,
    /// Whether the localization is the screened search's quick one (ranking the shortlist)
    /// rather than a full one.
    quick: bool,
    warnings: &'a [String],
}

#[derive(Debug, Serialize)]
struct Output<'a> {
    partial: &'a Path,
    /// Every shape searched, in the order given (`shapes[i]` is `index` i).
    shapes: Vec<&'a Path>,
    seconds: f64,
    ranking: Vec<Ranked<'a>>,
}

pub fn run(args: Args) -> Result<(), CliError> {
    let options = args.options.to_options()?;
    let threads = args.options.given_names().contains(&"threads").then_some(options.threads);
    if args.shortlist == 0 {
        return Err(CliError::Usage("--shortlist must be at least 1".into()));
    }
    let given_screen = match args.fulls.iter().position(|p| has_extension(p, SCREEN_EXTENSION)) {
        Some(_) if args.fulls.len() > 1 => {
            return Err(CliError::Usage(format!("a .{SCREEN_EXTENSION} file is the whole library: give it alone")))
        }
        Some(i) => Some(Screen::load(&args.fulls[i])?),
        None => None,
    };
    let paths = match &given_screen {
        Some(screen) => super::index::screen_paths(screen, &args.fulls[0]),
        None => expand_fulls(&args.fulls)?,
    };
    let mut inputs: Vec<&Path> = paths.iter().map(PathBuf::as_path).collect();
    inputs.push(&args.partial);
    for out in [&args.json, &args.png].into_iter().flatten() {
        check_output_path(out, &inputs)?;
    }
    if let Some(dir) = &args.ply_dir {
        std::fs::create_dir_all(dir).map_err(|source| CliError::Output { path: dir.clone(), source })?;
    }
    if paths.iter().any(|p| has_extension(p, EXTENSION)) && args.options.given_names().iter().any(|&n| n != "threads") {
        eprintln!("warning: prepared shapes (.{EXTENSION}) keep the options they were prepared with; the options given apply to the meshes only");
    }
    let (partial, _) = read_input_mesh(&args.partial, args.drop_isolated)?;
    // Shapes are opened one at a time during the search: a missing or unreadable file is
    // reported now, before any work, not when its turn comes.
    for path in &paths {
        std::fs::File::open(path).map_err(|source| CliError::Core(dualspectra::Error::Io { path: path.clone(), source }))?;
    }
    let shapes: Vec<Shape> = paths
        .iter()
        .map(|p| Shape { path: p.clone(), name: p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default() })
        .collect();
    let t = Instant::now();
    let (bar, progress) = progress_bar(args.quiet, "search");
    let same = |o: &Options| Options { threads: 0, ..o.clone() };
    let mut first_options = None;
    let mut warned = false;
    let open = |i: usize, progress: &Progress| {
        let localizer = open_full(&shapes[i].path, &options, threads, args.drop_isolated, progress)?;
        let o = same(localizer.options());
        match &first_options {
            None => first_options = Some(o),
            Some(first) if *first != o && !warned => {
                warned = true;
                bar.suspend(|| {
                    eprintln!(
                        "warning: {} and {} were prepared with different options; scores compare best under the same options",
                        shapes[0].name, shapes[i].name
                    )
                });
            }
            Some(_) => {}
        }
        Ok::<_, CliError>(localizer)
    };
    let top = args.top.unwrap_or(usize::MAX);
    let screened = args.shortlist < shapes.len();
    let found = if screened {
        // Describing the shapes here takes the first 20 % of the progress.
        let (screen, rest) = match given_screen {
            Some(screen) => (screen, progress.clone()),
            None => (describe_for_screen(&paths, args.drop_isolated, &progress.sub(0.0, 0.2))?, progress.sub(0.2, 1.0)),
        };
        dualspectra::search_screened(&partial, &screen, options.scale, args.shortlist, open, top, &rest)
    } else {
        dualspectra::search_with(&partial, shapes.len(), open, top, &progress)
    };
    bar.finish_and_clear();
    // The partial's own errors (a closed partial, ...) name its file.
    let found: Vec<Match> = found.map_err(|e| match e {
        CliError::Core(e) => CliError::Core(e.in_file(&args.partial)),
        other => other,
    })?;
    let seconds = t.elapsed().as_secs_f64();
    let mut ranking = Vec::new();
    let mut drawn: Vec<(TriMesh, String)> = Vec::new();
    for (i, m) in found.iter().enumerate() {
        let shape = &shapes[m.index];
        let loc = m.localization.as_ref();
        let draw = args.png.is_some() && i < PICTURE_SHAPES;
        let mut full = reopen(&shape.path, args.drop_isolated, draw || (args.ply_dir.is_some() && loc.is_some()))?;
        let (region, n_vertices) = match loc {
            Some(l) => full.file_region(&l.region),
            None => (Vec::new(), full.file_vertices()),
        };
        let rank = i + 1;
        if let (Some(dir), Some(l), Some(mesh)) = (&args.ply_dir, loc, &full.mesh) {
            let stem = Path::new(&shape.name).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            write_region_ply(&dir.join(format!("{rank}_{stem}.ply")), mesh, &l.region)?;
        }
        if let (true, Some(mesh)) = (draw, full.mesh.take()) {
            let score = if m.score.is_finite() { format!("{:.2e}", m.score) } else { "failed".to_string() };
            drawn.push((mesh, score));
        }
        ranking.push(Ranked {
            rank,
            shape: &shape.path,
            score: m.score.is_finite().then_some(m.score),
            region_vertices: region.len(),
            n_vertices,
            confidence: loc.map(|_| m.confidence),
            localization_confidence: loc.map(|l| l.confidence),
            cost: loc.map(|l| l.cost),
            region,
            error: m.error.as_deref(),
            screen_score: m.screen_score,
            quick: m.quick,
            warnings: loc.map_or(&[], |l| l.warnings.as_slice()),
        });
    }
    let name_width = ranking.iter().map(|r| shapes[found[r.rank - 1].index].name.len()).max().unwrap_or(5).max(5);
    let mut table = format!("{:>4}  {:<name_width$}  {:>10}  {:>16}  {:>10}\n", "rank", "shape", "score", "region", "confidence");
    for (r, m) in ranking.iter().zip(&found) {
        let name = &shapes[m.index].name;
        match (r.score, r.confidence) {
            (Some(score), Some(confidence)) => table.push_str(&format!(
                "{:>4}  {name:<name_width$}  {score:>10.4e}  {:>16}  {confidence:>10.2}{}\n",
                r.rank,
                format!("{}/{}", r.region_vertices, r.n_vertices),
                if r.quick { "  (quick)" } else { "" }
            )),
            _ => match (r.error, m.screen_score) {
                (None, Some(screen)) => table.push_str(&format!("{:>4}  {name:<name_width$}  screened out (screen score {screen:.4})\n", r.rank)),
                (error, _) => table.push_str(&format!("{:>4}  {name:<name_width$}  failed: {}\n", r.rank, error.unwrap_or("no region"))),
            },
        }
    }
    for (r, m) in ranking.iter().zip(&found) {
        for w in r.warnings {
            eprintln!("warning: {}: {w}", shapes[m.index].name);
        }
    }
    let out = Output { partial: &args.partial, shapes: paths.iter().map(PathBuf::as_path).collect(), seconds, ranking };
    if let Some(path) = &args.json {
        write_text(path, &to_json_line(&out)?)?;
    }
    if let Some(path) = &args.png {
        let pictured: Vec<render::Ranked> = drawn
            .iter()
            .zip(&found)
            .enumerate()
            .map(|(i, ((mesh, score), m))| render::Ranked {
                label: format!("{}. {}", i + 1, shapes[m.index].name),
                score: score.clone(),
                mesh,
                region: m.localization.as_ref().map(|l| l.region.as_slice()),
            })
            .collect();
        render::write_png(path, &render::ranking_picture(&pictured)?)?;
        table.push_str(&format!(
            "{}: ranks 1 to {}, each from the front and the back, region in red\n",
            path.display(),
            pictured.len()
        ));
    }
    let in_full = found.iter().filter(|m| m.localization.is_some() && !m.quick).count();
    if screened && found.iter().any(|m| m.quick) {
        table.push_str(&format!(
            "{} shapes screened, the {} best localized quickly and {} of those in full, in {seconds:.2} s\n",
            paths.len(),
            args.shortlist.min(paths.len()),
            refined_in_full(in_full)
        ));
    } else if screened {
        table.push_str(&format!("{} shapes screened, the {} best localized, in {seconds:.2} s\n", paths.len(), args.shortlist));
    } else {
        table.push_str(&format!("{} shapes searched in {seconds:.2} s\n", paths.len()));
    }
    print_stdout(&table)
}

/// How the summary line names the shapes a two-stage search localized again in full: "the
/// best" for one, "the N best" for more.
fn refined_in_full(count: usize) -> String {
    if count == 1 { "the best".to_string() } else { format!("the {count} best") }
}

#[cfg(test)]
mod tests {
    use super::refined_in_full;

    #[test]
    fn one_refined_shape_is_the_best() {
        assert_eq!(refined_in_full(1), "the best");
        assert_eq!(refined_in_full(2), "the 2 best");
    }
}
