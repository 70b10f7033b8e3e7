//! Typed errors. Every failure of the library is one of these; nothing panics on bad input.

use std::path::PathBuf;

/// Why a mesh was rejected. Each variant names the offending element.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    #[error("mesh has no faces")]
    NoFaces,
    #[error("all {count} faces are degenerate (zero area or a repeated vertex)")]
    AllFacesDegenerate { count: usize },
    #[error("mesh has no vertices")]
    NoVertices,
    #[error("face {face} refers to vertex {index}, but the mesh has {n_vertices} vertices")]
    IndexOutOfRange { face: usize, index: u64, n_vertices: usize },
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFiniteCoordinate { vertex: usize },
    #[error("face {face} repeats a vertex")]
    RepeatedVertexInFace { face: usize },
    #[error("face {face} has zero area (degenerate)")]
    DegenerateFace { face: usize },
    #[error("face {face} has the same three vertices as face {first} (a triangle given twice)")]
    RepeatedFace { face: usize, first: usize },
    #[error("edge ({a}, {b}) is shared by {count} faces (non-manifold)")]
    NonManifoldEdge { a: u32, b: u32, count: usize },
    #[error("vertex {vertex} belongs to no face (isolated); {count} isolated vertices in all")]
    IsolatedVertex { vertex: usize, count: usize },
    #[error("vertex {vertex} is non-manifold (its faces form {fans} separate fans)")]
    NonManifoldVertex { vertex: usize, fans: usize },
    #[error("array length {len} is not a multiple of {stride}")]
    BadArrayLength { len: usize, stride: usize },
    /// A partial shape must have a boundary: a closed surface has no Dirichlet spectrum.
    #[error(
        "the partial shape has no boundary (it is closed): there is no Dirichlet spectrum to match; \
         compare whole shapes with the similarity tools instead"
    )]
    ClosedPartial,
    /// A partial shape with more area than the full shape (after the `scale` option): it
    /// cannot be a part of it. `hint` names the option when the units may differ.
    #[error("the partial shape's area is {ratio:.3}x the full shape's: it cannot be a part of it{hint}")]
    PartialLargerThanFull { ratio: f64, hint: &'static str },
    /// A partial shape whose vertices are all on its boundary: its Dirichlet spectrum is empty.
    #[error("the partial shape has no interior vertex (every vertex is on its boundary): its Dirichlet spectrum is empty")]
    NoInteriorVertex,
}

/// Any error of the library.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    #[error("{path}: {source}")]
    InvalidMeshFile { path: PathBuf, source: MeshError },
    #[error("invalid mesh: {0}")]
    InvalidMesh(#[from] MeshError),
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// A prepared-shape file (or bytes) that cannot be loaded: foreign, stale (another format
    /// version), truncated or corrupted ([`crate::localizer::persist`]).
    #[error("{}: {message}", path.display())]
    PreparedShape { path: PathBuf, message: String },
    #[error("numerical failure: {0}")]
    Numerical(String),
    #[error("cancelled")]
    Cancelled,
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// Attach a file path to a mesh validation error.
    pub fn in_file(self, path: impl Into<PathBuf>) -> Error {
        match self {
            Error::InvalidMesh(source) => Error::InvalidMeshFile { path: path.into(), source },
            other => other,
        }
    }
}
