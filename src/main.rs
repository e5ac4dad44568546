//! The `flexbody` command line: a thin layer over the library. Arguments
//! become a validated configuration, then one library call does the work.
//! Exit status 0 on success, 2 on any error (bad input, failed reduction,
//! failed write), with the error on stderr.

use anyhow::Result;
use clap::{Parser, Subcommand};
use export::vtu::Encoding as VtuEncoding;
use flexbody::file_kind::Takes;
use flexbody::io::deck::{DeckOptions, UnknownKeywords};
use flexbody::linalg::memory::Budget;
use flexbody::linalg::progress::Progress;
use flexbody::output_folder::OutputFolder;
use flexbody::reduce::{reduce_keeping, Keep, Method, Reduction};
use flexbody::report::{self, Check};
use flexbody::simulate::Vehicle;
use flexbody::{
    export, input, output, plot, reduce as red, report_html, scenario, simulate, study,
};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

mod stage_log;

#[global_allocator]
static ALLOCATOR: flexbody::huge_pages::HugePages = flexbody::huge_pages::HugePages;

/// `println!` that ends the program quietly when stdout is closed (`| head`),
/// instead of panicking on the broken pipe.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
        }
    }};
}

#[derive(Parser)]
#[command(
    name = "flexbody",
    version,
    about = "Reduce linear FE models to flexible bodies for multibody simulation, and measure how accurate they are.",
    long_about = "Reduce linear FE models to flexible bodies for multibody simulation (after Dietz & Knothe 1997), couple them into MBS equations, recover section forces, and measure the accuracy against the full model.\n\nAll quantities are SI: m, kg, s, N, Pa, rad; excitation frequencies in rad/s, natural frequencies in Hz."
)]
struct Cli {
    /// Log each stage of the linear algebra (ordering, factorisation,
    /// Lanczos steps, solves) with its time on stderr.
    #[arg(long, short, global = true)]
    verbose: bool,
    /// Refuse a factorisation or eigen solve that would exceed GIB GiB of
    /// memory (free memory is always checked).
    #[arg(long, global = true, value_name = "GIB", value_parser = parse_gib)]
    max_memory: Option<u64>,
    /// Skip unknown deck keywords with one warning instead of refusing the
    /// deck (they may have changed K, M or D).
    #[arg(long, global = true)]
    allow_unknown: bool,
    /// No progress lines on stderr (warnings and errors still show).
    #[arg(long, short, global = true, conflicts_with = "verbose")]
    quiet: bool,
    /// Write through a symbolic link given as an output file (--out,
    /// --vtu, --report): the file it leads to is replaced, the link kept.
    /// Without it such a link is refused, as are devices and FIFOs.
    #[arg(long, global = true)]
    follow_symlinks: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Compare reduction methods against the full model (the [study] table of a model file).
    Study {
        /// Model file (TOML).
        model: PathBuf,
        /// Print the table as JSON: {"cases":[{"method","r","omega","err_w","err_m","err_q","err_force","err_vm"}],"failed":[{"method","modes","error"}]} (err_m, err_q for beams; err_vm for solids).
        #[arg(long)]
        json: bool,
        /// Directory for the SVG plots (default: out/<model name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Do not write plots.
        #[arg(long)]
        no_plots: bool,
        /// Also write one self-contained HTML page (for a design review):
        /// the run, the model, the error table and every plot inline.
        #[arg(long, value_name = "FILE.html")]
        report: Option<PathBuf>,
    },
    /// Reduce a model to a flexible body and write it (JSON, SID or Matrix Market; a VTU of its modes with --vtu).
    #[command(after_help = METHODS_HELP)]
    Reduce {
        /// Model file (.toml), deck (.inp), CalculiX matrices (job.sti) or Matrix Market stiffness (.mtx).
        model: PathBuf,
        /// Interface: comma-separated node sets or node numbers (all DOFs of
        /// each node). Default: the model file's interface, else the
        /// reference nodes of the model's couplings.
        #[arg(long)]
        interface: Option<String>,
        #[command(flatten)]
        matrices: MatrixArgs,
        /// Reduction method: free, craig-bampton, elastic-residual,
        /// free-residual or guyan (see below).
        #[arg(long, value_parser = parse_method)]
        method: Method,
        /// Eigenmodes e, counted as the method counts them (see below);
        /// required unless --fmax is given (guyan takes none).
        #[arg(long)]
        modes: Option<usize>,
        /// Instead of --modes: every eigenmode below this frequency (Hz), the
        /// report's e = modes in the excitation band.
        #[arg(long, value_parser = parse_frequency)]
        fmax: Option<f64>,
        /// Reduced-body file to write (a folder for --format mtx).
        #[arg(long)]
        out: PathBuf,
        /// Format: json (one file), sid (Standard Input Data for MBS codes),
        /// mtx (a folder of Matrix Market files with index.json), mbdyn
        /// (MBDyn's modal .fem file; needs node coordinates).
        #[arg(long, default_value = "json", value_parser = parse_format)]
        format: export::Format,
        /// Also write the mesh with every mode shape and its stresses for
        /// ParaView (.vtu; needs a mesh).
        #[arg(long)]
        vtu: Option<PathBuf>,
        /// Write the --vtu file as ASCII (default: zlib-compressed binary).
        #[arg(long, requires = "vtu")]
        vtu_ascii: bool,
        /// Rotate the basis so that M_red = I and K_red is diagonal.
        #[arg(long)]
        orthonormalize: bool,
        /// Print {"r":..,"full_hz":[..],"reduced_hz":[..]} instead of the table.
        #[arg(long)]
        json: bool,
        /// Compare with the full model's lowest r frequencies.
        #[arg(long, value_enum, default_value_t = Check::Auto)]
        check: Check,
    },
    /// Run the vehicle model of a model file in time ([simulation] table).
    Simulate {
        /// Model file (TOML) with a [simulation] table.
        model: PathBuf,
        /// Output directory: histories.csv and SVG plots.
        #[arg(long)]
        out: PathBuf,
        /// Integrate the full FE model instead of the reduced body (the reference).
        #[arg(long)]
        full: bool,
    },
    /// Transfer functions from the track to connection and section forces ([frf] table).
    Frf {
        /// Model file (TOML) with an [frf] table.
        model: PathBuf,
        /// Output directory: frf.csv and SVG plots.
        #[arg(long)]
        out: PathBuf,
        /// Use the full FE model instead of the reduced body.
        #[arg(long)]
        full: bool,
    },
    /// Print the summary of a reduced-body file (json, sid or an mtx folder).
    Inspect {
        /// Reduced-body file or folder.
        body: PathBuf,
        /// Print the summary as JSON: {"format","r","mass_kg","interface_nodes","frequencies_hz",..}.
        #[arg(long)]
        json: bool,
    },
    /// Convert a reduced-body file: a SID of any dialect (flexbody, welib,
    /// PY_SID) to flexbody's SID; a JSON body to a Matrix Market folder and
    /// back.
    Convert {
        /// Reduced-body file or Matrix Market folder.
        input: PathBuf,
        /// Format to write: sid (from a SID), json or mtx (from a JSON or
        /// Matrix Market body).
        #[arg(long, value_parser = parse_format)]
        format: export::Format,
        /// File to write (a folder for --format mtx).
        #[arg(long)]
        out: PathBuf,
    },
    /// Read and assemble a model; print its size, sets, couplings, materials, sections, fixed DOFs and mass, and the time and memory it took (with --factor, the size of its sparse factor).
    Info {
        /// Model file (.toml), deck (.inp), CalculiX matrices (job.sti) or Matrix Market stiffness (.mtx).
        model: PathBuf,
        #[command(flatten)]
        matrices: MatrixArgs,
        /// Also order and analyse the sparse factor of K - sigma M as
        /// `modes` and `reduce` do, and print its entries, its size in
        /// memory, its flops per factorisation and the memory left: what a
        /// large model's solve will take, before running it.
        #[arg(long)]
        factor: bool,
    },
    /// Natural frequencies of a model (free, or with its boundary conditions).
    Modes {
        /// Model file (.toml), deck (.inp), CalculiX matrices (job.sti) or Matrix Market stiffness (.mtx).
        model: PathBuf,
        #[command(flatten)]
        matrices: MatrixArgs,
        /// Number of modes, lowest first (all of them where the model has
        /// fewer); default 10 without --fmax. With --fmax, at most this many
        /// of the modes below it.
        #[arg(long, visible_alias = "modes")]
        count: Option<usize>,
        /// Every mode below this frequency (Hz), counted by the Sturm
        /// sequence; with --count N, only the lowest N of them.
        #[arg(long, value_parser = parse_frequency)]
        fmax: Option<f64>,
        /// Print {"dofs":..,"frequencies_hz":[..],"residuals":[..]}.
        #[arg(long)]
        json: bool,
    },
}

/// What `--modes` means for each method, after `reduce --help`.
const METHODS_HELP: &str = "\
Methods (r = the body's coordinates; --modes gives e):
  free              free-interface eigenmodes only; --modes is r in all,
                    rigid-body modes included. Fine for w, poor for forces.
  craig-bampton     e eigenmodes with the interface held, plus one static
                    constraint mode per interface DOF (r = e + interface DOFs).
  elastic-residual  e eigenmodes on the connections as elastic supports,
                    plus static residual modes (the report's best for
                    section forces).
  free-residual     e free elastic eigenmodes, the rigid-body modes, plus
                    inertia-relief residual modes per interface DOF or force
                    group; needs no static support at the interface.
  guyan             static condensation on the interface DOFs; no
                    eigenmodes (--modes 0 or omitted).
--fmax F instead of --modes takes every eigenmode below F Hz.";

/// Extra files for Matrix Market input.
#[derive(clap::Args)]
struct MatrixArgs {
    /// Matrix Market mass matrix (with a .mtx stiffness).
    #[arg(long)]
    mass: Option<PathBuf>,
    /// DOF map of the matrices: one `node dof` line per equation (with a .mtx stiffness).
    #[arg(long)]
    dofs: Option<PathBuf>,
    /// Node coordinates for matrix input: one `node x y z` line per node (m),
    /// for rigid-body modes from geometry and a SID.
    #[arg(long)]
    coords: Option<PathBuf>,
}

impl MatrixArgs {
    fn files(&self) -> input::MatrixFiles {
        input::MatrixFiles {
            mass: self.mass.clone(),
            dofs: self.dofs.clone(),
            coords: self.coords.clone(),
        }
    }
}

fn parse_format(s: &str) -> Result<export::Format, String> {
    s.parse()
}

/// A positive number of GiB, in bytes.
fn parse_gib(s: &str) -> Result<u64, String> {
    match s.parse::<f64>() {
        Ok(g) if g.is_finite() && g > 0.0 => Ok((g * (1u64 << 30) as f64) as u64),
        _ => Err(format!("'{s}' is not a positive number of GiB")),
    }
}

fn parse_method(s: &str) -> Result<Method, String> {
    Method::parse(s).ok_or_else(|| {
        let names: Vec<&str> = Method::ALL.iter().map(|m| m.name()).collect();
        format!(
            "unknown method '{s}'; expected one of: {}",
            names.join(", ")
        )
    })
}

/// `--fmax`: a positive, finite frequency in Hz (NaN would ask for no
/// eigenmode at all).
fn parse_frequency(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(f) if f.is_finite() && f > 0.0 => Ok(f),
        _ => Err(format!("'{s}' is not a positive frequency in Hz")),
    }
}

fn main() -> ExitCode {
    flexbody::linalg::memory::tune_allocator();
    let start = std::time::Instant::now();
    let cli = Cli::parse();
    let progress = stage_log::install(stage_log::Mode::of(cli.verbose, cli.quiet), start);
    let result = run(cli, &*progress);
    // The terminal display is cleared before an error is printed.
    drop(progress);
    stage_log::finish();
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", message(&e));
            ExitCode::from(2)
        }
    }
}

/// The error and its causes, `outer: inner: ...`
/// ([`flexbody::io::text::error_chain`]).
fn message(e: &anyhow::Error) -> String {
    flexbody::io::text::error_chain(e.as_ref())
}

fn run(cli: Cli, progress: &dyn Progress) -> Result<()> {
    let budget = Budget::at_most(cli.max_memory);
    let deck = DeckOptions {
        allow_unknown: cli.allow_unknown,
        memory: budget,
    };
    let follow = cli.follow_symlinks;
    let output = |path: PathBuf| output_path(path, follow);
    let output_opt = |path: Option<PathBuf>| path.map(output).transpose();
    match cli.command {
        Command::Study {
            model,
            json,
            out,
            no_plots,
            report,
        } => run_study(
            &model,
            json,
            (out, no_plots, output_opt(report)?),
            deck,
            budget,
            progress,
        ),
        Command::Reduce {
            model,
            interface,
            matrices,
            method,
            modes,
            fmax,
            out,
            format,
            vtu,
            vtu_ascii,
            orthonormalize,
            json,
            check,
        } => {
            let (out, vtu) = (output(out)?, output_opt(vtu)?);
            run_reduce(
                &model,
                interface.as_deref(),
                &matrices,
                deck,
                method,
                (modes, fmax),
                (
                    &out,
                    format,
                    vtu.as_deref().map(|p| (p, vtu_encoding(vtu_ascii))),
                ),
                orthonormalize,
                (json, check),
                budget,
                progress,
            )
        }
        Command::Modes {
            model,
            matrices,
            count,
            fmax,
            json,
        } => {
            let band = modes_wanted(count, fmax)?;
            run_modes(&model, &matrices, deck, band, json, budget, progress)
        }
        Command::Info {
            model,
            matrices,
            factor,
        } => run_info(&model, &matrices, deck, factor, budget),
        Command::Inspect { body, json } => {
            Takes::INSPECT.check(&body)?;
            let read = export::read_any(&body)?;
            if json {
                say!("{}", serde_json::to_string_pretty(&read.summary_json())?);
            } else {
                say!("{}", read.summary());
            }
            Ok(())
        }
        Command::Convert { input, format, out } => {
            Takes::CONVERT.check(&input)?;
            let out = output(out)?;
            let read = export::convert(&input, format, &out)?;
            let from = match &read {
                export::AnyBody::Sid(_, dialect) => format!("SID, {dialect}"),
                export::AnyBody::Reduced(..) => "reduced body".into(),
            };
            say!("wrote {} ({format}, from a {from})", out.display());
            Ok(())
        }
        Command::Simulate { model, out, full } => {
            Takes::SIMULATE.check(&model)?;
            run_simulate(&model, &out, full, deck, budget, progress)
        }
        Command::Frf { model, out, full } => {
            Takes::FRF.check(&model)?;
            run_frf(&model, &out, full, deck, budget, progress)
        }
    }
}

/// An output file's path as given, or with `follow` the file a symbolic
/// link there leads to (which must exist or be creatable: a dangling link
/// is an error naming it).
fn output_path(path: PathBuf, follow: bool) -> Result<PathBuf> {
    let is_link = std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink());
    if !(follow && is_link) {
        return Ok(path);
    }
    let target = std::fs::read_link(&path)
        .map_err(|e| anyhow::anyhow!("{}: cannot read the symbolic link: {e}", path.display()))?;
    let target = match path.parent() {
        Some(dir) if target.is_relative() => dir.join(target),
        _ => target,
    };
    // A link to a link: resolved to its end by the system (whose bound on
    // chains stops a loop).
    if std::fs::symlink_metadata(&target).is_ok_and(|m| m.file_type().is_symlink()) {
        return std::fs::canonicalize(&target).map_err(|e| {
            anyhow::anyhow!(
                "{}: the symbolic link leads to {}, which cannot be resolved: {e}",
                path.display(),
                target.display()
            )
        });
    }
    Ok(target)
}

fn run_study(
    model: &Path,
    json: bool,
    (out, no_plots, html): (Option<PathBuf>, bool, Option<PathBuf>),
    deck: DeckOptions,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<()> {
    let dir = (!no_plots).then(|| {
        out.unwrap_or_else(|| {
            let stem = model
                .file_stem()
                .map_or("study".into(), |s| s.to_string_lossy().into_owned());
            Path::new("out").join(stem)
        })
    });
    Takes::STUDY.check(model)?;
    let file = scenario::read_model_file_with(model, &deck)?;
    warn_deck(&file.notes, &file.warnings, &file.unknown_keywords);
    if let Some(path) = &html {
        export::check_writable(path)?;
    }
    let folder = dir
        .as_deref()
        .map(|d| {
            let omegas = file.study.as_ref().map_or(&[][..], |s| &s.omegas[..]);
            OutputFolder::make(d, &plot::first_study_plot(omegas))
        })
        .transpose()?;
    let result = study::run_study(&file, budget, progress)?;
    if let Some(dir) = &dir {
        plot::plot_study(dir, &result).map_err(anyhow::Error::msg)?;
    }
    if let Some(path) = &html {
        let run = report_html::RunInfo::of_this_process();
        report_html::write_study_report(path, &file, &result, &run)?;
    }
    if let Some(folder) = folder {
        folder.keep();
    }
    if json {
        let doc = serde_json::json!({ "cases": result.rows(), "failed": result.failures });
        say!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        say!(
            "{}",
            report::study_table(&result, file.model.dof_map().len())
        );
        if let Some(dir) = dir {
            say!("plots: {}", dir.display());
        }
        if let Some(path) = &html {
            say!("report: {}", path.display());
        }
    }
    match result.failures.len() {
        0 => Ok(()),
        n => anyhow::bail!(
            "{n} of {} study cases failed (the table names why)",
            n + result.cases.len() / result.references.len().max(1)
        ),
    }
}

/// The component at `model`, for the command that `takes` it.
fn load(
    model: &Path,
    matrices: &MatrixArgs,
    takes: Takes,
    deck: DeckOptions,
) -> Result<input::Component> {
    takes.check(model)?;
    let c = input::load_with(model, &matrices.files(), &deck)?;
    warn_deck(&c.notes, &c.warnings, &c.unknown_keywords);
    Ok(c)
}

/// A deck's notes and warnings (each naming its deck), then the one
/// warning listing the deck keywords skipped by `--allow-unknown`.
fn warn_deck(notes: &[String], warnings: &[String], unknown: &UnknownKeywords) {
    for n in notes {
        eprintln!("note: {n}");
    }
    for w in warnings {
        eprintln!("warning: {w}");
    }
    if let Some(summary) = unknown.summary() {
        eprintln!("warning: {summary}");
    }
}

#[allow(clippy::too_many_arguments)]
fn run_reduce(
    model: &Path,
    interface: Option<&str>,
    matrices: &MatrixArgs,
    deck: DeckOptions,
    method: Method,
    (modes, fmax): (Option<usize>, Option<f64>),
    (out, format, vtu): (&Path, export::Format, Option<(&Path, VtuEncoding)>),
    orthonormalize: bool,
    (json, check): (bool, Check),
    budget: Budget,
    progress: &dyn Progress,
) -> Result<()> {
    // A wrong output path fails now, not after the reduction.
    match format {
        export::Format::Mtx => export::check_folder_writable(out, "index.json")?,
        _ => export::check_writable(out)?,
    }
    if let Some((path, _)) = vtu {
        export::check_writable(path)?;
    }
    let mut c = load(model, matrices, Takes::REDUCE, deck)?;
    if format == export::Format::Mbdyn && !c.sub.has_geometry() {
        anyhow::bail!(
            "{}: --format mbdyn needs node coordinates (MBDyn's record groups 5-7) and \
             matrices alone have none: give them with `--coords NODES.txt`, or reduce the \
             model file or deck the matrices came from",
            model.display()
        );
    }
    if vtu.is_some() && c.model.is_none() {
        anyhow::bail!(
            "{}: --vtu needs a mesh; matrices alone have none",
            model.display()
        );
    }
    // The assembly's work arrays go back before the factorisations.
    flexbody::linalg::memory::release_free_memory();
    let modes = reduce_modes(method, modes, fmax)?;
    let interface = match interface {
        Some(given) => c.interface(Some(given))?,
        None => match c.default_interface() {
            Some(default) => {
                eprintln!(
                    "note: interface: {}; --interface names another",
                    default.source
                );
                default.dofs
            }
            None if method != Method::Free => anyhow::bail!(
                "{}: the {method} method needs interface DOFs and none are given: name them with \
                 --interface SETS_OR_NODES (comma-separated; {}), or give the model file an \
                 [interface] table or connections, or the deck a *COUPLING (its reference \
                 node becomes the interface)",
                model.display(),
                c.node_set_list()
            ),
            None => Vec::new(),
        },
    };
    let mut spec = match &c.file {
        Some(file) => input::file_reduction(file, method, modes, interface),
        None => Reduction::new(method, modes, interface),
    };
    if let Some(model) = &c.model {
        spec.local_axes = model.local_axes().clone();
    }
    spec.max_frequency_hz = fmax;
    spec.orthonormalize = orthonormalize;
    spec.memory = budget;
    let compare = check.compares(c.sub.len());
    // K and M are needed after the reduction only by the comparison, and
    // M by the invariants of SID and MBDyn; the solver drops what is not.
    let keep = if compare {
        Keep::Both
    } else if matches!(format, export::Format::Sid | export::Format::Mbdyn) {
        Keep::Mass
    } else {
        Keep::Neither
    };
    let body = reduce_keeping(&mut c.sub, &spec, keep, progress)?;
    stage_log::step(&format!(
        "reduced: r = {} (writing {})",
        body.r(),
        out.display()
    ));
    let comparison = report::compare_frequencies(&c.sub, &body, compare, budget, progress)?;
    let (full_hz, reduced_hz) = (&comparison.full_hz, &comparison.reduced_hz);
    let metadata = output::index_metadata(&comparison);
    let files = output::body_output(&c.sub, c.model.as_ref(), &body, format, metadata)?;
    export::write(&files, format, out)?;
    stage_log::step(&format!("written: {}", out.display()));
    let mut written = vec![match format {
        export::Format::Mtx => format!(
            "{} (a folder: index.json and a Matrix Market file per matrix)",
            out.display()
        ),
        _ => out.display().to_string(),
    }];
    if let (Some((path, encoding)), Some(mesh)) = (vtu, &c.model) {
        stage_log::step(&format!("writing the mode shapes to {}", path.display()));
        export::vtk::write_vtu(mesh, &output::mode_fields(mesh, &body)?, encoding, path)?;
        stage_log::step(&format!("written: {}", path.display()));
        written.push(format!("{} (mode shapes for ParaView)", path.display()));
    }
    if json {
        let doc =
            serde_json::json!({ "r": body.r(), "full_hz": full_hz, "reduced_hz": reduced_hz });
        say!("{}", serde_json::to_string_pretty(&doc)?);
        return Ok(());
    }
    say!(
        "{} reduction, r = {}, written to {}",
        method,
        body.r(),
        written.join(" and ")
    );
    match full_hz {
        Some(full_hz) => {
            say!("{:>5} {:>14} {:>14}", "mode", "full (Hz)", "reduced (Hz)");
            for (i, (f, r)) in full_hz.iter().zip(reduced_hz).enumerate() {
                say!("{:>5} {:>14.6} {:>14.6}", i + 1, f, r);
            }
        }
        None => {
            if check == Check::Never {
                say!("(no comparison with the full model: --check never)");
            } else {
                say!(
                    "(no comparison with the full model above {} DOFs; --check always adds it)",
                    Check::AUTO_UP_TO
                );
            }
            say!("{:>5} {:>14}", "mode", "reduced (Hz)");
            for (i, r) in reduced_hz.iter().enumerate() {
                say!("{:>5} {:>14.6}", i + 1, r);
            }
        }
    }
    Ok(())
}

/// The eigenmodes `reduce` asks for: `--modes`, or none beside `--fmax`
/// and for `guyan`; every other method needs one of the two.
fn reduce_modes(method: Method, modes: Option<usize>, fmax: Option<f64>) -> Result<usize> {
    match (modes, fmax) {
        (Some(m), _) => Ok(m),
        (None, Some(_)) => Ok(0),
        (None, None) if method == Method::Guyan => Ok(0),
        (None, None) => anyhow::bail!(
            "the {method} method needs --modes N (its eigenmodes e; for free the total r, \
             rigid-body modes included) or --fmax F (every eigenmode below F Hz); \
             `flexbody reduce --help` says what each method counts"
        ),
    }
}

/// The encoding of the `--vtu` file: binary unless `--vtu-ascii`.
fn vtu_encoding(ascii: bool) -> VtuEncoding {
    if ascii {
        VtuEncoding::Ascii
    } else {
        VtuEncoding::Binary
    }
}

/// The modes `flexbody modes` computes: `--count` (default 10), every one
/// below `--fmax` (positive, checked by [`parse_frequency`]), or, with both
/// given, the lowest `--count` below `--fmax`.
fn modes_wanted(count: Option<usize>, fmax: Option<f64>) -> Result<red::modes::Wanted> {
    use red::modes::Wanted;
    if count == Some(0) {
        anyhow::bail!("--count must be at least 1");
    }
    Ok(match (count, fmax) {
        (None, Some(f)) => Wanted::below_hz(f),
        (Some(count), Some(f)) => Wanted::lowest_below_hz(count, f),
        (count, None) => Wanted::Lowest(count.unwrap_or(10)),
    })
}

fn run_modes(
    model: &Path,
    matrices: &MatrixArgs,
    deck: DeckOptions,
    band: red::modes::Wanted,
    json: bool,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<()> {
    let modes = report::natural_frequencies(
        load(model, matrices, Takes::MODES, deck)?,
        band,
        budget,
        progress,
    )?;
    if let Some(mechanism) = &modes.mechanism {
        eprintln!("warning: {}: {mechanism}", model.display());
    }
    let (n, hz, residuals) = (modes.dofs, &modes.frequencies_hz, &modes.residuals);
    if json {
        let doc = serde_json::json!({ "dofs": n, "frequencies_hz": hz, "residuals": residuals });
        say!("{}", serde_json::to_string_pretty(&doc)?);
        return Ok(());
    }
    say!("{n} DOFs");
    say!("{:>5} {:>14} {:>10}", "mode", "f (Hz)", "residual");
    for (i, (f, r)) in hz.iter().zip(residuals).enumerate() {
        say!("{:>5} {:>14.6} {:>10.1e}", i + 1, f, r);
    }
    Ok(())
}

fn run_info(
    model: &Path,
    matrices: &MatrixArgs,
    deck: DeckOptions,
    factor: bool,
    budget: Budget,
) -> Result<()> {
    let start = std::time::Instant::now();
    let c = load(model, matrices, Takes::INFO, deck)?;
    let seconds = start.elapsed().as_secs_f64();
    let map = &c.sub.dof_map;
    say!("{}", c.path.display());
    if let Some(m) = &c.model {
        say!("nodes {}, elements {}", m.nodes().len(), m.elements().len());
    } else {
        say!("matrices only (no mesh: element stresses and section forces need the mesh)");
    }
    say!(
        "DOFs {}, nonzeros of K {}",
        map.len(),
        c.sub.matrices.stiffness.compute_nnz()
    );
    let masses: Vec<String> = report::mass_along_axes(&c.sub)
        .iter()
        .map(|m| format!("{m:.6e}"))
        .collect();
    say!("mass along x, y, z (kg), free DOFs: {}", masses.join(", "));
    for line in flexbody::model_summary::lines(&c)? {
        say!("{line}");
    }
    say!(
        "read in {:.3} s, assembled in {:.3} s ({seconds:.3} s in all); peak memory {}",
        c.timing.0,
        c.timing.1,
        peak_memory()
    );
    if factor {
        use flexbody::linalg::memory;
        say!("{}", report::factor_size(&c.sub)?);
        if let Some(room) = budget.room() {
            say!(
                "memory left: {} ({})",
                memory::bytes_text(room.bytes),
                room.bound
            );
        }
    }
    Ok(())
}

/// Peak resident memory of this process (Linux), or "unknown".
fn peak_memory() -> String {
    flexbody::linalg::memory::process_memory().map_or("unknown".into(), |(_, peak)| {
        format!("{:.3} GB", peak as f64 / (1u64 << 30) as f64)
    })
}

/// The vehicle of a model file and its output folder, made before the
/// body is reduced (unless `full`), so that a bad path fails first.
fn vehicle(
    model: &Path,
    (out, first): (&Path, &str),
    full: bool,
    deck: DeckOptions,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<(Vehicle, OutputFolder)> {
    let v = Vehicle::read_with(model, &deck)?;
    warn_deck(&v.file.notes, &v.file.warnings, &v.file.unknown_keywords);
    let folder = OutputFolder::make(out, first)?;
    Ok((
        if full {
            v
        } else {
            v.reduced(budget, progress)?
        },
        folder,
    ))
}

fn run_simulate(
    model: &Path,
    out: &Path,
    full: bool,
    deck: DeckOptions,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<()> {
    let (v, folder) = vehicle(model, (out, "histories.csv"), full, deck, budget, progress)?;
    let h = simulate::run_simulation(&v.file, v.flexible())?;
    let csv = out.join("histories.csv");
    flexbody::export::columns::write_columns(&csv, "time (s)", &h.times, &h.columns)?;
    folder.keep();
    let plots = plot::plot_histories(out, &h, v.label()).map_err(anyhow::Error::msg)?;
    say!(
        "{} steps to t = {} s ({}); wrote {}",
        h.times.len() - 1,
        h.times.last().copied().unwrap_or(0.0),
        v.label(),
        written_list(&csv, &plots)
    );
    say!("{:<40} {:>14} {:>14}", "history", "min", "max");
    for (name, lo, hi) in h.ranges() {
        say!("{name:<40} {lo:>14.5e} {hi:>14.5e}");
    }
    Ok(())
}

fn run_frf(
    model: &Path,
    out: &Path,
    full: bool,
    deck: DeckOptions,
    budget: Budget,
    progress: &dyn Progress,
) -> Result<()> {
    let (v, folder) = vehicle(model, (out, "frf.csv"), full, deck, budget, progress)?;
    let t = simulate::run_frf(&v.file, v.flexible())?;
    let csv = out.join("frf.csv");
    flexbody::export::columns::write_columns(&csv, "f (Hz)", &t.frequencies_hz, &t.columns())?;
    folder.keep();
    let plots =
        plot::plot_transfer(out, &t, v.file.connections.len()).map_err(anyhow::Error::msg)?;
    say!("damped modes of the coupled system (eq. 21, connections linearized at rest):");
    match simulate::coupled_modes_if_dense(&v.file, v.flexible())? {
        Err(why) => say!("  not computed: {why}"),
        Ok(modes) => {
            say!(
                "{:>5} {:>14} {:>14} {:>10}",
                "mode",
                "natural (Hz)",
                "damped (Hz)",
                "zeta"
            );
            for (k, m) in modes.iter().enumerate() {
                say!(
                    "{:>5} {:>14.4} {:>14.4} {:>10.4}",
                    k + 1,
                    m.natural_hz,
                    m.damped_hz,
                    m.damping_ratio
                );
            }
        }
    }
    say!("wrote {}", written_list(&csv, &plots));
    Ok(())
}

/// "out/histories.csv, out/connections.svg and out/histories.svg".
fn written_list(csv: &Path, plots: &[PathBuf]) -> String {
    let mut all: Vec<String> = std::iter::once(csv)
        .chain(plots.iter().map(PathBuf::as_path))
        .map(|p| p.display().to_string())
        .collect();
    match all.pop() {
        Some(last) if !all.is_empty() => format!("{} and {last}", all.join(", ")),
        Some(last) => last,
        None => String::new(),
    }
}
