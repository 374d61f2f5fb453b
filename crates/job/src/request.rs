//! [`Request`]: what a front end asks of a run, with the one table of defaults and the one place
//! that validates it (before any mesh is read). The CLI builds it from its flags, Python from its
//! keywords, the batch from its own flags, the facade and the viewer from their settings.

use crate::JobError;
use gng3d_core::{GngOptions, GngTarget, Placement, Shape, SignalSource};
use std::fmt;
use std::str::FromStr;

/// GNG3D's seed when none is given, in every front end (the CLI's `--seed`, Python's `seed=`,
/// the batch, the facade): one value, so the same file gives the same mesh everywhere.
pub const DEFAULT_SEED: u64 = 1;

/// The method every front end runs when none is named: QEM. It is the best of the simplifiers
/// measured on distance (README, "Verdict"), the fastest, and the one that keeps texture
/// coordinates, normals and colours through its contractions; GNG3D-Q is the choice for a
/// fixed vertex count with even triangles (`--method gng`).
pub const DEFAULT_METHOD: Method = Method::Qem;

/// Most threads a request may ask for (`threads`): a fixed bound, not the machine's core count,
/// so that a request valid on one machine is valid on every one (the mesh does not depend on the
/// count). Far above any useful count; it keeps a typo such as 10000 from starting a pool of
/// 10,000 threads.
pub const MAX_THREADS: usize = 256;

/// A simplification method, named the same way in every front end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Method {
    /// Garland–Heckbert quadric error metrics (pair contraction): `qem`.
    Qem,
    /// GNG3D-Q, the project's GNG3D (quadric placement, oversampling, repairs): `gng`.
    Gng,
    /// The published GNG3D (node placement, 30 epochs, no oversampling): `paper`.
    Paper,
}

impl Method {
    /// Every method, in the order the front ends list them.
    pub const ALL: [Method; 3] = [Method::Qem, Method::Gng, Method::Paper];

    /// The method's name (`qem`, `gng`, `paper`).
    pub fn name(self) -> &'static str {
        match self {
            Method::Qem => "qem",
            Method::Gng => "gng",
            Method::Paper => "paper",
        }
    }

    /// The name in messages ("QEM", "GNG3D").
    pub fn label(self) -> &'static str {
        match self {
            Method::Qem => "QEM",
            Method::Gng | Method::Paper => "GNG3D",
        }
    }

    /// Whether this is one of the GNG3D methods.
    pub fn is_gng(self) -> bool {
        matches!(self, Method::Gng | Method::Paper)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = JobError;
    fn from_str(s: &str) -> Result<Method, JobError> {
        parse_name("method", s, &Method::ALL, |m| m.name())
    }
}

/// What a run does with the input's normals, texture coordinates, colours and materials.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[non_exhaustive]
pub enum AttributePolicy {
    /// Carry them to the output (QEM through its contractions, GNG3D from the original's
    /// surface), written where the output format stores them: `keep`.
    #[default]
    Keep,
    /// Positions and triangles only, as if the file had none: `drop`.
    Drop,
}

impl AttributePolicy {
    /// Both policies.
    pub const ALL: [AttributePolicy; 2] = [AttributePolicy::Keep, AttributePolicy::Drop];

    /// The policy's name (`keep`, `drop`).
    pub fn name(self) -> &'static str {
        match self {
            AttributePolicy::Keep => "keep",
            AttributePolicy::Drop => "drop",
        }
    }
}

impl fmt::Display for AttributePolicy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for AttributePolicy {
    type Err = JobError;
    fn from_str(s: &str) -> Result<AttributePolicy, JobError> {
        parse_name("attributes", s, &AttributePolicy::ALL, |p| p.name())
    }
}

/// The names of GNG3D's vertex placements (`node`, `project`, `quadric`).
pub fn placement_name(p: Placement) -> &'static str {
    match p {
        Placement::Node => "node",
        Placement::Project => "project",
        Placement::Quadric => "quadric",
    }
}

/// The placement named `s` (`node`, `project`, `quadric`).
pub fn parse_placement(s: &str) -> Result<Placement, JobError> {
    parse_name(
        "placement",
        s,
        &[Placement::Node, Placement::Project, Placement::Quadric],
        placement_name,
    )
}

/// The names of GNG3D's signal sources (`vertices`, `surface`, `curvature`).
pub fn signals_name(s: SignalSource) -> &'static str {
    match s {
        SignalSource::Vertices => "vertices",
        SignalSource::Surface => "surface",
        SignalSource::Curvature => "curvature",
    }
}

/// The signal source named `s` (`vertices`, `surface`, `curvature`).
pub fn parse_signals(s: &str) -> Result<SignalSource, JobError> {
    parse_name(
        "signals",
        s,
        &[
            SignalSource::Vertices,
            SignalSource::Surface,
            SignalSource::Curvature,
        ],
        signals_name,
    )
}

/// The names of GNG3D-Q's triangle-shape settings (`off`, `fit`, `round`).
pub fn shape_name(s: Shape) -> &'static str {
    match s {
        Shape::Off => "off",
        Shape::Fit => "fit",
        Shape::Round => "round",
    }
}

/// The triangle-shape setting named `s` (`off`, `fit`, `round`).
pub fn parse_shape(s: &str) -> Result<Shape, JobError> {
    parse_name(
        "shape",
        s,
        &[Shape::Off, Shape::Fit, Shape::Round],
        shape_name,
    )
}

/// The value of `option` named `s` among `all`, or an error listing the names.
fn parse_name<T: Copy>(
    option: &'static str,
    s: &str,
    all: &[T],
    name: impl Fn(T) -> &'static str,
) -> Result<T, JobError> {
    all.iter().copied().find(|v| name(*v) == s).ok_or_else(|| {
        let names: Vec<String> = all.iter().map(|v| format!("'{}'", name(*v))).collect();
        JobError::Option {
            option: Opt::named(option),
            message: format!("must be {}, got {s:?}", or_list(&names)),
        }
    })
}

/// "a, b or c".
fn or_list(names: &[String]) -> String {
    match names {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// How big the output is to be.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum Target {
    /// This many vertices (every method).
    Vertices(usize),
    /// A share of the input's referenced vertices in (0, 1], for every method (rounded to the
    /// nearest count: 0.1 gives the same count with QEM and GNG3D).
    Ratio(f64),
    /// This many faces (QEM only).
    Faces(usize),
    /// A share of the input's faces in (0, 1] (QEM only).
    FaceRatio(f64),
    /// No size: QEM simplifies as far as [`QemOptions::max_error`] allows (which must be set).
    MaxErrorOnly,
}

/// The GNG3D variant: every field `None` keeps the method's default (GNG3D-Q for
/// [`Method::Gng`], the published protocol for [`Method::Paper`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GngVariant {
    /// Vertex placement (`--placement`, `placement=`).
    pub placement: Option<Placement>,
    /// The error-driven edge flips (`--no-flips`, `flips=`).
    pub flips: Option<bool>,
    /// The surface refit (`--no-refit`, `refit=`).
    pub refit: Option<bool>,
    /// The tangential relaxation (`--no-relax`, `relax=`).
    pub relax: Option<bool>,
    /// The deviation repair (`--no-deviation-repair`, `deviation_repair=`).
    pub deviation_repair: Option<bool>,
    /// The signal budget in epochs (`--epochs`, `epochs=`).
    pub epochs: Option<f64>,
    /// Where training signals come from (`--signals`, `signals=`).
    pub signals: Option<SignalSource>,
    /// GNG3D-Q's oversampling factor (`--oversample`, `oversample=`).
    pub oversample: Option<f64>,
    /// GNG3D-Q's rounds of detail nodes (`--detail-rounds`, `detail_rounds=`).
    pub detail_rounds: Option<usize>,
    /// GNG3D-Q's triangle-shape pass after the decimation (`--shape[=fit|round|off]`,
    /// `shape="fit"`; `ReconstructionParams::shape`, docs/notes/shape.md).
    pub shape: Option<Shape>,
    /// GNG3D-Q's CAD creases (`--creases`, `creases=`; `ReconstructionParams::creases`,
    /// docs/notes/creases.md).
    pub creases: Option<bool>,
}

impl GngVariant {
    /// The options given (they apply to GNG3D only).
    pub fn given(&self) -> Vec<Opt> {
        [
            (self.placement.is_some(), Opt::Placement),
            (self.flips.is_some(), Opt::Flips),
            (self.refit.is_some(), Opt::Refit),
            (self.relax.is_some(), Opt::Relax),
            (self.deviation_repair.is_some(), Opt::DeviationRepair),
            (self.epochs.is_some(), Opt::Epochs),
            (self.signals.is_some(), Opt::Signals),
            (self.oversample.is_some(), Opt::Oversample),
            (self.detail_rounds.is_some(), Opt::DetailRounds),
            (self.shape.is_some(), Opt::Shape),
            (self.creases.is_some(), Opt::Creases),
        ]
        .into_iter()
        .filter_map(|(given, opt)| given.then_some(opt))
        .collect()
    }

    /// Writes the variant into `options` (validated with them by `GngOptions::validate`): the
    /// one mapping of every front end's GNG3D flags, keywords and settings.
    pub fn apply(&self, options: &mut GngOptions) {
        if let Some(p) = self.placement {
            options.reconstruction.placement = p;
        }
        if let Some(f) = self.flips {
            options.reconstruction.flip_edges = f;
        }
        if let Some(r) = self.refit {
            options.reconstruction.refit = r;
        }
        if let Some(r) = self.relax {
            options.reconstruction.relax = r;
        }
        if let Some(r) = self.deviation_repair {
            options.reconstruction.repair_deviations = r;
        }
        if let Some(s) = self.signals {
            options.signal_source = s;
        }
        if self.epochs.is_some() {
            options.epochs = self.epochs;
            options.max_signals = None;
        }
        if self.oversample.is_some() {
            options.oversample = self.oversample;
        }
        if self.detail_rounds.is_some() {
            options.detail_rounds = self.detail_rounds;
        }
        if let Some(s) = self.shape {
            options.reconstruction.shape = s;
        }
        if let Some(c) = self.creases {
            options.reconstruction.creases = c;
        }
    }
}

/// QEM's options besides the target.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct QemOptions {
    /// Pair distance threshold in model units (0: edges only).
    pub threshold: f64,
    /// Never contract the vertices on the input's border edges.
    pub lock_border: bool,
    /// Stop rule as a share of the bounding-box diagonal.
    pub max_error: Option<f64>,
    /// Weights of the attribute error in the collapse cost.
    pub attribute_weights: Option<qem::AttributeWeights>,
}

/// One option of a [`Request`], for messages: each front end spells it its own way
/// ([`Opt::flag`] for the command line, [`Opt::keyword`] for Python).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
#[allow(missing_docs)]
pub enum Opt {
    Method,
    Target,
    Ratio,
    FaceRatio,
    FaceTarget,
    Seed,
    Threads,
    TimeLimit,
    Attributes,
    Placement,
    Flips,
    Refit,
    Relax,
    DeviationRepair,
    Epochs,
    Signals,
    Oversample,
    DetailRounds,
    Shape,
    Creases,
    Threshold,
    LockBorder,
    MaxError,
    AttributeWeights,
    Partition,
    MemoryBudget,
}

/// Every option with its command-line flag and its Python keyword.
const SPELLINGS: [(Opt, &str, &str); 26] = [
    (Opt::Method, "--method", "method"),
    (
        Opt::Target,
        "--vertices/--ratio/--faces",
        "vertices_target/ratio/faces_target",
    ),
    (Opt::Ratio, "--ratio", "ratio"),
    (Opt::FaceRatio, "--face-ratio", "face_ratio"),
    (Opt::FaceTarget, "--faces/--face-ratio", "faces_target"),
    (Opt::Seed, "--seed", "seed"),
    (Opt::Threads, "--threads", "threads"),
    (Opt::TimeLimit, "--time-limit", "time_limit"),
    (Opt::Attributes, "--attributes", "attributes"),
    (Opt::Placement, "--placement", "placement"),
    (Opt::Flips, "--no-flips", "flips"),
    (Opt::Refit, "--no-refit", "refit"),
    (Opt::Relax, "--no-relax", "relax"),
    (
        Opt::DeviationRepair,
        "--no-deviation-repair",
        "deviation_repair",
    ),
    (Opt::Epochs, "--epochs", "epochs"),
    (Opt::Signals, "--signals", "signals"),
    (Opt::Oversample, "--oversample", "oversample"),
    (Opt::DetailRounds, "--detail-rounds", "detail_rounds"),
    (Opt::Shape, "--shape", "shape"),
    (Opt::Creases, "--creases", "creases"),
    (Opt::Threshold, "--threshold", "threshold"),
    (Opt::LockBorder, "--lock-border", "lock_border"),
    (Opt::MaxError, "--max-error", "max_error"),
    (
        Opt::AttributeWeights,
        "--attribute-weights",
        "attribute_weights",
    ),
    (Opt::Partition, "--partition", "partition"),
    (Opt::MemoryBudget, "--memory-budget", "memory_budget"),
];

impl Opt {
    /// The command line's flag.
    pub fn flag(self) -> &'static str {
        SPELLINGS.iter().find(|s| s.0 == self).map_or("", |s| s.1)
    }

    /// Python's keyword.
    pub fn keyword(self) -> &'static str {
        SPELLINGS.iter().find(|s| s.0 == self).map_or("", |s| s.2)
    }

    /// The option whose keyword is `keyword` (`Target` when there is none).
    fn named(keyword: &str) -> Opt {
        SPELLINGS
            .iter()
            .find(|s| s.2 == keyword)
            .map_or(Opt::Target, |s| s.0)
    }
}

impl fmt::Display for Opt {
    /// The keyword, which every front end understands ("time_limit").
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.keyword())
    }
}

/// Everything a front end asks of one run. [`Request::new`] gives the defaults of every front end
/// (the one table: [`DEFAULT_METHOD`], [`DEFAULT_SEED`], welding on, attributes kept, the
/// machine's threads); [`Request::validate`] is the one check.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    /// The method.
    pub method: Method,
    /// The output's size.
    pub target: Target,
    /// GNG3D's random seed.
    pub seed: u64,
    /// Most threads the run uses (`None`: the machine's, GNG3D's training at most 4).
    pub threads: Option<usize>,
    /// GNG3D's most seconds for the whole run.
    pub time_limit: Option<f64>,
    /// What happens to the input's attributes.
    pub attributes: AttributePolicy,
    /// Weld exact duplicate positions and drop degenerate faces and unreferenced vertices
    /// before the run (the CLI's `--no-weld` and Python's `weld=False` turn it off).
    pub weld: bool,
    /// GNG3D's variant.
    pub gng: GngVariant,
    /// QEM's options.
    pub qem: QemOptions,
    /// Whether the mesh is held in memory or streamed through the partition
    /// ([`crate::Partition::Auto`]: QEM on positions only, for a mesh larger than memory).
    pub partition: crate::Partition,
}

impl Request {
    /// The defaults of every front end for `target`.
    pub fn new(target: Target) -> Request {
        Request {
            method: DEFAULT_METHOD,
            target,
            seed: DEFAULT_SEED,
            threads: None,
            time_limit: None,
            attributes: AttributePolicy::Keep,
            weld: true,
            gng: GngVariant::default(),
            qem: QemOptions::default(),
            partition: crate::Partition::Off,
        }
    }

    /// `self` with `method`.
    pub fn with_method(self, method: Method) -> Request {
        Request { method, ..self }
    }

    /// Every check that does not need the mesh: the options that do not apply to the method,
    /// the target's range, and the libraries' own checks (`GngOptions::validate`,
    /// `QemParams::validate`). The first problem found, naming its option.
    pub fn validate(&self) -> Result<(), JobError> {
        if let Some(t) = self.threads
            && !(1..=MAX_THREADS).contains(&t)
        {
            return Err(JobError::option(
                Opt::Threads,
                format!("must be in 1 to {MAX_THREADS}, got {t}"),
            ));
        }
        match self.target {
            Target::Ratio(r) if !(r > 0.0 && r <= 1.0) => {
                return Err(JobError::option(
                    Opt::Ratio,
                    format!("must be in (0, 1], got {r}"),
                ));
            }
            Target::FaceRatio(r) if !(r > 0.0 && r <= 1.0) => {
                return Err(JobError::option(
                    Opt::FaceRatio,
                    format!("must be in (0, 1], got {r}"),
                ));
            }
            _ => {}
        }
        if let crate::Partition::Auto(options) = &self.partition {
            crate::partitioned::validate(self, options)?;
        }
        if self.method.is_gng() {
            let mut refused = Vec::new();
            if matches!(self.target, Target::Faces(_) | Target::FaceRatio(_)) {
                return Err(JobError::NotForMethod {
                    options: vec![Opt::FaceTarget],
                    method: self.method,
                    detail: "a face count or share applies to QEM only; give a vertex count or a share of the vertices",
                });
            }
            if self.target == Target::MaxErrorOnly {
                return Err(JobError::NoTarget);
            }
            let q = &self.qem;
            if q.threshold != 0.0 {
                refused.push(Opt::Threshold);
            }
            if q.lock_border {
                refused.push(Opt::LockBorder);
            }
            if q.max_error.is_some() {
                refused.push(Opt::MaxError);
            }
            if q.attribute_weights.is_some() {
                refused.push(Opt::AttributeWeights);
            }
            if !refused.is_empty() {
                return Err(JobError::NotForMethod {
                    options: refused,
                    method: self.method,
                    detail: "they apply to QEM only",
                });
            }
            self.gng_options()?
                .validate()
                .map_err(|e| JobError::Gng(Box::new(e)))?;
        } else {
            let mut refused = self.gng.given();
            if self.time_limit.is_some() {
                refused.insert(0, Opt::TimeLimit);
            }
            if !refused.is_empty() {
                return Err(JobError::NotForMethod {
                    options: refused,
                    method: self.method,
                    detail: "they apply to GNG3D only",
                });
            }
            if self.target == Target::MaxErrorOnly && self.qem.max_error.is_none() {
                return Err(JobError::NoTarget);
            }
            if !(self.qem.threshold >= 0.0 && self.qem.threshold.is_finite()) {
                return Err(JobError::option(
                    Opt::Threshold,
                    format!("must be a finite distance >= 0, got {}", self.qem.threshold),
                ));
            }
            // --max-error alone first, so its error names the option (the library's words).
            qem::QemParams {
                max_relative_error: self.qem.max_error,
                ..qem::QemParams::default()
            }
            .validate()
            .map_err(|e| JobError::option(Opt::MaxError, e.to_string()))?;
            self.qem_params(qem::Target::Faces(0))
                .validate()
                .map_err(|e| JobError::Qem(Box::new(e)))?;
        }
        Ok(())
    }

    /// GNG3D's options of this request (its target must be a vertex count or share).
    pub fn gng_options(&self) -> Result<GngOptions, JobError> {
        let target = match self.target {
            Target::Vertices(n) => GngTarget::Vertices(n),
            Target::Ratio(r) => GngTarget::VertexRatio(r),
            _ => return Err(JobError::NoTarget),
        };
        let mut options = match self.method {
            Method::Paper => GngOptions::paper(target),
            _ => GngOptions::for_target(target),
        };
        options.seed = self.seed;
        options.time_limit_seconds = self.time_limit;
        options.threads = self.threads;
        self.gng.apply(&mut options);
        Ok(options)
    }

    /// QEM's parameters of this request for `target` (the cancel flag is set by the run).
    pub fn qem_params(&self, target: qem::Target) -> qem::QemParams {
        let mut params = qem::QemParams {
            target,
            pair_threshold: self.qem.threshold,
            max_relative_error: self.qem.max_error,
            lock: if self.qem.lock_border {
                qem::Lock::Border
            } else {
                qem::Lock::None
            },
            ..qem::QemParams::default()
        };
        if let Some(w) = self.qem.attribute_weights {
            params.attribute_weights = w;
        }
        params
    }

    /// QEM's target on `mesh`: a share of the vertices through the one mapping
    /// (`GngTarget::vertex_count`, rounded to the nearest count), as GNG3D's.
    pub fn qem_target(&self, mesh: &mesh::TriMesh) -> Result<qem::Target, JobError> {
        Ok(match self.target {
            Target::Vertices(n) => qem::Target::Vertices(n),
            Target::Faces(n) => qem::Target::Faces(n),
            Target::Ratio(r) => qem::Target::Vertices(
                GngTarget::VertexRatio(r)
                    .vertex_count(mesh)
                    .map_err(|e| JobError::Gng(Box::new(e)))?,
            ),
            Target::FaceRatio(r) => qem::Target::Ratio(r),
            Target::MaxErrorOnly => qem::Target::Faces(0),
        })
    }
}
