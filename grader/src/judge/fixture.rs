//! The fixture format: one JSON file per case, written by the fixture
//! generator and read here. Documented in `docs/fixtures.md`.
//!
//! Files are written by [`to_json_text`]: stable key order, one vertex or
//! edge per line, floats as shortest round-trip decimals, so regenerating
//! unchanged fixtures rewrites the same bytes and a diff shows what moved.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// The schema version this grader reads and the fixture generator writes.
/// 3: a mistake's broken mesh is `validate()`'s check by its key, not its
/// message.
pub const SCHEMA: u32 = 3;

/// The oldest schema whose cases (not their expected results) the
/// generator still reads back, to regenerate a TA's own cases.
pub const OLDEST_CASE_SCHEMA: u32 = 2;

/// One graded case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fixture {
    pub schema: u32,
    /// Unique, also the file name without `.json`: `cube-flip`.
    pub name: String,
    /// The mesh's name in messages: `cube`.
    pub object: String,
    pub group: Group,
    pub input: MeshData,
    pub operation: Operation,
    /// For a sequence: its flips and splits, in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<Step>,
    /// The vertex weight rule the expected result used.
    pub weights: WeightRule,
    /// How far (Euclidean) a vertex may be from its expected position.
    pub tolerance: f64,
    pub expected: Expected,
}

/// Which set a case belongs to; also its folder under `fixtures/`.
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Serialize,
    Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum Group {
    /// The four lab objects: these decide the verdict.
    Lab,
    /// Meshes with boundary: reported apart, counted only with `--bonus`.
    Bonus,
    /// Withheld from the handout; counted like `lab` when present.
    Hidden,
}

impl Group {
    pub const ALL: [Group; 3] = [Group::Lab, Group::Bonus, Group::Hidden];

    pub fn name(self) -> &'static str {
        match self {
            Group::Lab => "lab",
            Group::Bonus => "bonus",
            Group::Hidden => "hidden",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WeightRule {
    Warren,
    Loop,
}

/// A mesh as indexed polygons.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshData {
    pub positions: Vec<[f64; 3]>,
    pub faces: Vec<Vec<usize>>,
}

impl MeshData {
    /// A mesh as indexed polygons (its real faces).
    pub fn from_mesh(mesh: &halfedge::Mesh) -> MeshData {
        let (positions, faces) = mesh.to_faces();
        MeshData {
            positions: positions.iter().map(|p| p.to_array()).collect(),
            faces,
        }
    }

    /// Builds the mesh, with every check of `Mesh::from_faces`.
    pub fn to_mesh(&self) -> Result<halfedge::Mesh, halfedge::MeshError> {
        let positions: Vec<halfedge::DVec3> = self
            .positions
            .iter()
            .map(|p| halfedge::DVec3::from_array(*p))
            .collect();
        halfedge::Mesh::from_faces(&positions, &self.faces)
    }
}

/// What the case does to the input mesh. Edges are named by their two
/// endpoints' input indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Operation {
    Flip {
        edge: [usize; 2],
    },
    Split {
        edge: [usize; 2],
    },
    Subdivide {
        rounds: usize,
    },
    /// The fixture's `steps`, one after another on the same mesh; `seed`
    /// is the one that drew them, for messages.
    Sequence {
        seed: u64,
    },
}

/// One operation of a sequence. `edge` names two vertices: input indices,
/// or `n + k` for the vertex the k-th split made (counting from 0, `n`
/// the number of input vertices), so ids stay stable along the sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Step {
    Flip { edge: [usize; 2] },
    Split { edge: [usize; 2] },
}

impl Step {
    pub fn edge(self) -> [usize; 2] {
        match self {
            Step::Flip { edge } | Step::Split { edge } => edge,
        }
    }
    pub fn is_split(self) -> bool {
        matches!(self, Step::Split { .. })
    }
    pub fn function(self) -> &'static str {
        if self.is_split() {
            "split_edge"
        } else {
            "flip_edge"
        }
    }
}

impl Operation {
    /// The stage it tests, as `--stage` names it.
    pub fn stage(self) -> Stage {
        match self {
            Operation::Flip { .. } => Stage::Flip,
            Operation::Split { .. } => Stage::Split,
            Operation::Subdivide { .. } => Stage::Subdivide,
            Operation::Sequence { .. } => Stage::Sequence,
        }
    }
}

/// The three functions, then flips and splits in sequence, graded in
/// this order. Every name a stage goes by is in [`STAGE_NAMES`].
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Serialize,
    Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum Stage {
    Flip,
    Split,
    /// Flips and splits in sequence.
    Sequence,
    Subdivide,
}

/// What the lab calls a stage, wherever it is named: `--stage` and the
/// fixtures and JSON (`key`), the messages (`function`: "flip_edge
/// returned ..."), the summary's tally (`tally`), the case's lines ("start
/// testing `heading` for ...", the original lab's words), the platforms'
/// test names and tables (`title`), result columns (`column`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct StageNames {
    pub key: &'static str,
    pub function: &'static str,
    pub tally: &'static str,
    pub heading: &'static str,
    pub title: &'static str,
    pub column: &'static str,
}

/// Every stage's names, in grading order: the one list every crate, page
/// and script reads (scripts through the JSON report's `stages`).
pub const STAGE_NAMES: [StageNames; 4] = [
    StageNames {
        key: "flip",
        function: "flip_edge",
        tally: "flip_edge",
        heading: "flip_edge",
        title: "flip_edge",
        column: "flip_edge",
    },
    StageNames {
        key: "split",
        function: "split_edge",
        tally: "split_edge",
        heading: "split_edge",
        title: "split_edge",
        column: "split_edge",
    },
    StageNames {
        key: "sequence",
        function: "flip_edge and split_edge",
        tally: "in sequence",
        heading: "flips and splits in sequence",
        title: "flips and splits in sequence",
        column: "in_sequence",
    },
    StageNames {
        key: "subdivide",
        function: "loop_subdivide",
        tally: "loop_subdivide",
        heading: "subdivision",
        title: "loop_subdivide",
        column: "loop_subdivide",
    },
];

impl Stage {
    /// Every stage, in grading order.
    pub const ALL: [Stage; 4] = [Stage::Flip, Stage::Split, Stage::Sequence, Stage::Subdivide];

    /// Its names (see [`StageNames`]).
    pub fn names(self) -> &'static StageNames {
        &STAGE_NAMES[self as usize]
    }

    /// The function a message names: "flip_edge returned ...".
    pub fn function(self) -> &'static str {
        self.names().function
    }

    /// How `--stage`, the fixtures and the JSON name it: `flip`.
    pub fn key(self) -> &'static str {
        self.names().key
    }

    /// The stages whose functions this stage's function calls
    /// (`loop_subdivide` calls `split_edge` and `flip_edge`): when they
    /// fail their own cases, a failure here may be theirs.
    pub fn calls(self) -> &'static [Stage] {
        match self {
            Stage::Subdivide => &[Stage::Split, Stage::Flip],
            Stage::Flip | Stage::Split | Stage::Sequence => &[],
        }
    }
}

/// The expected result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Expected {
    /// What the function returns: `null` for `loop_subdivide` and for a
    /// sequence.
    pub returns: Option<Returns>,
    /// For a sequence: what each step returns, in the steps' stable ids.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<Returns>,
    pub positions: Vec<[f64; 3]>,
    /// Every edge as a pair of indices into `positions`, smaller first, sorted.
    pub edges: Vec<[usize; 2]>,
    /// Results of known mistakes, so that a wrong answer that matches one can
    /// be named. Each keeps the expected vertex numbering.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mistakes: Vec<Mistake>,
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Returns {
    /// `None`: the operation must refuse and change nothing.
    Refused,
    /// `Some(e)` for the edge given, which now joins `ends` (input indices).
    Edge { ends: [usize; 2] },
    /// `Some(v)` for a new vertex at `position`, whose halfedge runs to one
    /// of the split edge's ends.
    Vertex { position: [f64; 3] },
    /// `loop_subdivide` must panic, with a message that says a face is not
    /// a triangle.
    Panic,
}

/// The smallest and largest tolerance a fixture may have, as fractions of
/// the input mesh's size (the diagonal of its bounding box).
pub const TOLERANCE_RANGE: (f64, f64) = (1e-12, 1e-2);

/// The diagonal of the bounding box of `positions` (0 for none).
pub fn mesh_size(positions: &[[f64; 3]]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if positions.is_empty() {
        return 0.0;
    }
    (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt()
}

/// Why a tolerance is out of range for a mesh of this size, if it is: "must
/// be between LO and HI for this mesh (...)". The bounds are compared as
/// printed (4 digits), so a value copied from the message is accepted.
pub fn tolerance_problem(tolerance: f64, size: f64) -> Option<String> {
    if !(size > 0.0 && size.is_finite()) {
        return Some(format!(
            "the mesh has no size to measure a tolerance against (the diagonal of its bounding \
             box is {size}): all its vertices are at one point"
        ));
    }
    let shown = |x: f64| format!("{x:.3e}");
    let (lo, hi) = (
        shown(TOLERANCE_RANGE.0 * size),
        shown(TOLERANCE_RANGE.1 * size),
    );
    let (lo_f, hi_f): (f64, f64) = (lo.parse().unwrap_or(0.0), hi.parse().unwrap_or(0.0));
    if lo_f <= tolerance && tolerance <= hi_f {
        return None;
    }
    Some(format!(
        "must be between {lo} and {hi} for this mesh ({:e} to {:e} of its size, the diagonal \
         of its bounding box, {})",
        TOLERANCE_RANGE.0,
        TOLERANCE_RANGE.1,
        shown(size)
    ))
}

/// What a known mistake produces: positions, edges, or the broken link
/// `validate()` finds, where they differ from the expected result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Mistake {
    pub id: String,
    pub hint: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub positions: Option<Vec<[f64; 3]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edges: Option<Vec<[usize; 2]>>,
    /// The check of `validate()` the mistake fails when it breaks the mesh,
    /// stored by its key (`"duplicate-edge"`): a fact, never its words.
    #[serde(default, skip_serializing_if = "Option::is_none", with = "check_key")]
    pub invalid: Option<halfedge::Check>,
}

/// A `validate()` check in a fixture: its stable key.
mod check_key {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(c: &Option<halfedge::Check>, s: S) -> Result<S::Ok, S::Error> {
        match c {
            Some(c) => s.serialize_str(c.key()),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<halfedge::Check>, D::Error> {
        let key = Option::<String>::deserialize(d)?;
        key.map(|k| {
            halfedge::Check::from_key(&k).ok_or_else(|| {
                serde::de::Error::custom(format!("{k:?} is not a check of validate()"))
            })
        })
        .transpose()
    }
}

/// The case a fixture file describes, without its expected result: what
/// the generator needs to regenerate a TA's own case, from this schema or
/// an older one back to [`OLDEST_CASE_SCHEMA`] (whose expected part it
/// rewrites anyway).
#[derive(Clone, Debug, Deserialize)]
pub struct CaseFile {
    pub name: String,
    pub object: String,
    pub group: Group,
    pub input: MeshData,
    pub operation: Operation,
    #[serde(default)]
    pub steps: Vec<Step>,
    pub weights: WeightRule,
    pub tolerance: f64,
}

/// Reads a fixture file's case (see [`CaseFile`]), naming the file in
/// every error.
pub fn load_case(path: &Path) -> Result<CaseFile, FixtureError> {
    let err = |message: String| FixtureError {
        path: path.to_path_buf(),
        message,
    };
    let text = std::fs::read_to_string(path).map_err(|e| err(format!("cannot read: {e}")))?;
    let value: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| err(format!("not valid JSON: {e}")))?;
    match value.get("schema").and_then(|s| s.as_u64()) {
        Some(s) if (OLDEST_CASE_SCHEMA as u64..=SCHEMA as u64).contains(&s) => {}
        Some(s) => {
            return Err(err(format!(
                "schema {s}: this generator reads cases of schema {OLDEST_CASE_SCHEMA} to {SCHEMA}"
            )))
        }
        None => return Err(err("no \"schema\" number: is this a fixture file?".into())),
    }
    serde_json::from_value(value).map_err(|e| err(format!("not a valid fixture's case: {e}")))
}

/// Why fixtures could not be loaded: always names the file.
#[derive(Debug)]
pub struct FixtureError {
    pub path: PathBuf,
    pub message: String,
}

impl std::fmt::Display for FixtureError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for FixtureError {}

impl Fixture {
    /// Parses and checks one fixture file.
    pub fn from_json(text: &str, path: &Path) -> Result<Fixture, FixtureError> {
        let err = |message: String| FixtureError {
            path: path.to_path_buf(),
            message,
        };
        // Read the schema first, so an old or new file says so rather than
        // failing on some field it does not have.
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| err(format!("not valid JSON: {e}")))?;
        match value.get("schema").and_then(|s| s.as_u64()) {
            Some(s) if s == SCHEMA as u64 => {}
            Some(s) => {
                return Err(err(format!(
                    "schema {s}, but this grader reads schema {SCHEMA}: regenerate the fixtures \
                     or update the grader"
                )))
            }
            None => return Err(err("no \"schema\" number: is this a fixture file?".into())),
        }
        let fixture: Fixture =
            serde_json::from_value(value).map_err(|e| err(format!("not a valid fixture: {e}")))?;
        fixture.check().map_err(err)?;
        Ok(fixture)
    }

    /// Consistency a corrupted or hand-edited file could break.
    fn check(&self) -> Result<(), String> {
        let nin = self.input.positions.len();
        let nout = self.expected.positions.len();
        let finite = |ps: &[[f64; 3]]| ps.iter().flatten().all(|x| x.is_finite());
        if !finite(&self.input.positions) || !finite(&self.expected.positions) {
            return Err("a position is not a finite number".into());
        }
        if let Some(problem) = tolerance_problem(self.tolerance, mesh_size(&self.input.positions)) {
            return Err(format!(
                "tolerance {} is out of range: {problem}",
                self.tolerance
            ));
        }
        if let Some(face) = self
            .input
            .faces
            .iter()
            .find(|f| f.iter().any(|&i| i >= nin))
        {
            return Err(format!(
                "input face {face:?} refers to a vertex past the {nin} input positions"
            ));
        }
        if let Some(e) = self
            .expected
            .edges
            .iter()
            .find(|e| e[0] >= nout || e[1] >= nout)
        {
            return Err(format!(
                "expected edge {e:?} refers to a vertex past the {nout} expected positions"
            ));
        }
        if let Some(w) = self.expected.edges.windows(2).find(|w| w[0] >= w[1]) {
            return Err(format!(
                "expected edges {:?} and {:?} are not sorted and distinct",
                w[0], w[1]
            ));
        }
        if let Some(e) = self.expected.edges.iter().find(|e| e[0] >= e[1]) {
            return Err(format!(
                "expected edge {e:?} must list its smaller end first"
            ));
        }
        let edge_ok = |[a, b]: [usize; 2]| a < nin && b < nin && a != b;
        match self.operation {
            Operation::Flip { edge } | Operation::Split { edge } if !edge_ok(edge) => {
                return Err(format!(
                    "operation edge {edge:?} does not name two input vertices"
                ))
            }
            Operation::Subdivide { rounds: 0 } => {
                return Err("subdivide with 0 rounds tests nothing".into())
            }
            _ => {}
        }
        self.check_steps()?;
        let returns_fit = matches!(
            (self.operation, self.expected.returns),
            (
                Operation::Flip { .. },
                Some(Returns::Edge { .. } | Returns::Refused)
            ) | (
                Operation::Split { .. },
                Some(Returns::Vertex { .. } | Returns::Refused)
            ) | (Operation::Subdivide { .. }, None | Some(Returns::Panic))
                | (Operation::Sequence { .. }, None)
        );
        if !returns_fit {
            return Err(format!(
                "expected.returns {:?} does not fit the operation {:?}",
                self.expected.returns, self.operation
            ));
        }
        for m in &self.expected.mistakes {
            if m.positions.as_ref().is_some_and(|p| p.len() != nout) {
                return Err(format!(
                    "mistake {:?} has the wrong number of positions",
                    m.id
                ));
            }
        }
        Ok(())
    }

    /// A sequence has steps, each naming two vertices there are by then,
    /// and one expected return per step that fits it; other cases have none.
    fn check_steps(&self) -> Result<(), String> {
        let sequence = matches!(self.operation, Operation::Sequence { .. });
        if !sequence {
            if !self.steps.is_empty() || !self.expected.steps.is_empty() {
                return Err("only a sequence has steps".into());
            }
            return Ok(());
        }
        if self.steps.is_empty() {
            return Err("a sequence with no steps tests nothing".into());
        }
        if self.steps.len() != self.expected.steps.len() {
            return Err(format!(
                "{} steps but {} expected returns",
                self.steps.len(),
                self.expected.steps.len()
            ));
        }
        let mut known = self.input.positions.len();
        for (i, (step, want)) in self.steps.iter().zip(&self.expected.steps).enumerate() {
            let [a, b] = step.edge();
            if a >= known || b >= known || a == b {
                return Err(format!(
                    "step {} names edge {a}-{b}, but there are only {known} vertices by then",
                    i + 1
                ));
            }
            let fits = match (step, want) {
                (_, Returns::Refused) => true,
                (Step::Flip { .. }, Returns::Edge { ends }) => ends.iter().all(|&v| v < known),
                (Step::Split { .. }, Returns::Vertex { position }) => {
                    position.iter().all(|x| x.is_finite())
                }
                _ => false,
            };
            if !fits {
                return Err(format!(
                    "step {} expects {want:?}, which does not fit {step:?}",
                    i + 1
                ));
            }
            if matches!(want, Returns::Vertex { .. }) {
                known += 1;
            }
        }
        Ok(())
    }

    /// Builds the input mesh and checks the case makes sense on it: the mesh
    /// is valid and the operation's edge is one of its edges. An error here
    /// is the fixture's fault, never the student's.
    pub fn input_mesh(&self) -> Result<halfedge::Mesh, String> {
        let mesh = self
            .input
            .to_mesh()
            .map_err(|e| format!("the input mesh is not valid: {e}"))?;
        mesh.validate()
            .map_err(|e| format!("the input mesh is not valid: {e}"))?;
        if let Operation::Flip { edge: [a, b] } | Operation::Split { edge: [a, b] } = self.operation
        {
            if mesh.edge_between(a, b).is_none() {
                return Err(format!(
                    "the operation's edge {a}-{b} is not an edge of the input mesh"
                ));
            }
        }
        Ok(mesh)
    }

    /// The case's edge in the input mesh, for a flip or split.
    pub fn edge_in(&self, mesh: &halfedge::Mesh) -> Option<halfedge::EdgeId> {
        match self.operation {
            Operation::Flip { edge: [a, b] } | Operation::Split { edge: [a, b] } => {
                mesh.edge_between(a, b)
            }
            Operation::Subdivide { .. } | Operation::Sequence { .. } => None,
        }
    }

    /// The file this fixture lives in, under the fixtures root.
    pub fn relative_path(&self) -> PathBuf {
        Path::new(self.group.name()).join(format!("{}.json", self.name))
    }
}

/// The `*.json` files under `root/<group>/`, group by group, each group's
/// sorted by name. A missing group folder is skipped (the handout has no
/// `hidden/`).
pub fn fixture_files(root: &Path) -> Result<Vec<(Group, PathBuf)>, FixtureError> {
    let mut out = Vec::new();
    for group in Group::ALL {
        let dir = root.join(group.name());
        if !dir.is_dir() {
            continue;
        }
        let entries = std::fs::read_dir(&dir).map_err(|e| FixtureError {
            path: dir.clone(),
            message: e.to_string(),
        })?;
        let mut paths: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .collect();
        paths.sort();
        out.extend(paths.into_iter().map(|p| (group, p)));
    }
    Ok(out)
}

/// Reads and checks one fixture file.
pub fn load(path: &Path) -> Result<Fixture, FixtureError> {
    let text = std::fs::read_to_string(path).map_err(|e| FixtureError {
        path: path.to_path_buf(),
        message: format!("cannot read: {e}"),
    })?;
    Fixture::from_json(&text, path)
}

/// Loads every fixture under `root`, sorted by stage, then group, then
/// name. A missing root, an unreadable or invalid file, or a file in the
/// wrong folder or under the wrong name is an error naming it.
pub fn load_all(root: &Path) -> Result<Vec<Fixture>, FixtureError> {
    if !root.is_dir() {
        return Err(FixtureError {
            path: root.to_path_buf(),
            message: "no such fixtures folder (run from the lab's folder, or pass --fixtures DIR)"
                .into(),
        });
    }
    let mut all: Vec<Fixture> = Vec::new();
    for (group, path) in fixture_files(root)? {
        let fixture = load(&path)?;
        if let Some(twin) = all.iter().find(|f| f.name == fixture.name) {
            return Err(FixtureError {
                path,
                message: format!(
                    "a case named \"{}\" exists already in {}/: case names must be unique",
                    fixture.name,
                    twin.group.name()
                ),
            });
        }
        if fixture.group != group {
            return Err(FixtureError {
                path,
                message: format!(
                    "says group \"{}\" but lives in {}/",
                    fixture.group.name(),
                    group.name()
                ),
            });
        }
        if fixture.relative_path().file_name() != path.file_name() {
            return Err(FixtureError {
                path,
                message: format!("is named \"{}\" inside: rename one of them", fixture.name),
            });
        }
        all.push(fixture);
    }
    check_digests(root)?;
    all.sort_by(|a, b| {
        (a.operation.stage(), a.group, &a.name).cmp(&(b.operation.stage(), b.group, &b.name))
    });
    Ok(all)
}

/// Checks every group folder's files against its `SHA256SUMS`: each
/// fixture listed, each listed file present, each digest right.
pub fn check_digests(root: &Path) -> Result<(), FixtureError> {
    use crate::judge::digest;
    let err = |path: PathBuf, message: String| FixtureError { path, message };
    let mut by_group: Vec<(PathBuf, Vec<PathBuf>)> = Vec::new();
    for (group, path) in fixture_files(root)? {
        let dir = root.join(group.name());
        match by_group.last_mut() {
            Some((d, files)) if *d == dir => files.push(path),
            _ => by_group.push((dir, vec![path])),
        }
    }
    for (dir, files) in by_group {
        let sums = digest::read_sums(&dir).map_err(|m| err(dir.join(digest::SUMS_FILE), m))?;
        for path in &files {
            let name = path
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or_default();
            let Some((_, want)) = sums.iter().find(|(n, _)| n == name) else {
                return Err(err(
                    path.clone(),
                    format!(
                        "is not in {}: a fixture added by hand? Remove it, or ask a TA",
                        digest::SUMS_FILE
                    ),
                ));
            };
            let bytes = std::fs::read(path).map_err(|e| err(path.clone(), e.to_string()))?;
            if digest::sha256_hex(&bytes) != *want {
                return Err(err(
                    path.clone(),
                    format!(
                        "has been changed since the fixtures were generated (its SHA-256 is \
                         not the one in {}): restore it (git checkout fixtures/) or ask a TA",
                        digest::SUMS_FILE
                    ),
                ));
            }
        }
        for (name, _) in &sums {
            if !files
                .iter()
                .any(|p| p.file_name().is_some_and(|n| n == name.as_str()))
            {
                return Err(err(
                    dir.join(name),
                    format!("is listed in {} but missing", digest::SUMS_FILE),
                ));
            }
        }
    }
    Ok(())
}

/// The fixture as the JSON text the generator writes: objects indented,
/// arrays of numbers on one line.
pub fn to_json_text(fixture: &Fixture) -> String {
    let value = serde_json::to_value(fixture).expect("fixtures serialize");
    let mut out = String::new();
    write_value(&mut out, &value, 0);
    out.push('\n');
    out
}

fn write_value(out: &mut String, value: &serde_json::Value, indent: usize) {
    use serde_json::Value;
    let pad = |n: usize| "  ".repeat(n);
    match value {
        Value::Object(map) if !map.is_empty() => {
            out.push_str("{\n");
            for (i, (k, v)) in map.iter().enumerate() {
                let _ = write!(out, "{}{}: ", pad(indent + 1), Value::String(k.clone()));
                write_value(out, v, indent + 1);
                out.push_str(if i + 1 < map.len() { ",\n" } else { "\n" });
            }
            let _ = write!(out, "{}}}", pad(indent));
        }
        Value::Array(items) if items.iter().any(|v| v.is_array() || v.is_object()) => {
            out.push_str("[\n");
            for (i, v) in items.iter().enumerate() {
                out.push_str(&pad(indent + 1));
                write_value(out, v, indent + 1);
                out.push_str(if i + 1 < items.len() { ",\n" } else { "\n" });
            }
            let _ = write!(out, "{}]", pad(indent));
        }
        Value::Array(items) => {
            out.push('[');
            for (i, v) in items.iter().enumerate() {
                if i > 0 {
                    out.push_str(", ");
                }
                out.push_str(&v.to_string());
            }
            out.push(']');
        }
        other => out.push_str(&other.to_string()),
    }
}
