//! Partitioned builds (#40): a mesh cut into spatially compact parts of near-equal face
//! count, each simplified apart with its border fenced, and the parts' base domains joined
//! into one mesh that a build continues.
//!
//! The cut follows the Morton (Z-order) curve of the face centroids (Morton 1966), the
//! space-filling-curve partitioning of Pilkington & Baden 1996 ("Dynamic partitioning of
//! non-uniform structured workloads with spacefilling curves"): faces sorted by the
//! curve's key in the unit frame, then cut into runs of equal length. The curve keeps
//! neighbouring faces together, so a run is compact and its border short.
//!
//! A part's border vertices (on faces of another part too) are kept by its build and
//! fenced ([`super::SimplifyOptions::border_vertices`]): no flip or weld joins two of them
//! by a new edge, since the part cannot see the edges the other parts hold between them.
//! Every other vertex of a part has its whole star in the part, so the part's levels are
//! levels of the whole mesh, and the parts' bases join edge to edge along their unchanged
//! borders into a manifold ([`build_partitioned`] continues the build on it).
//!
//! A part can be built in another process ([`PartBuild`], [`files`]): `asperity simplify
//! plan` writes the parts, job runners build them, `asperity simplify merge` joins them.

mod build;
pub mod files;
pub(super) mod morton;
pub mod plan;

pub use build::{PartBuild, build_part, build_part_among, build_partitioned, join_parts, part_goal, separate_parts};

use rustc_hash::{FxHashMap, FxHashSet};

use crate::analysis::Quadric;
use crate::hierarchy::BOUNDARY_WEIGHT;

use crate::error::{Error, Result};
use crate::mesh::uv::{CornerUvs, Materials};
use crate::mesh::{Mesh, TopologyCounts, UnitFrame, split_non_manifold_fans};

/// Which part each face of a mesh belongs to, and which vertices lie on a border between
/// parts.
#[derive(Debug, Clone)]
pub struct Partition {
    owner: Vec<u32>,
    parts: usize,
    border: Vec<bool>,
    /// The faces grouped by part, each part's in input order:
    /// `faces[starts[k]..starts[k + 1]]` are part k's.
    faces: Vec<u32>,
    starts: Vec<usize>,
    /// The input's unit frame: each part's error bound is a fraction of its diagonal, and
    /// the quadrics a part hands over are in it.
    frame: UnitFrame,
    /// The part of each vertex's first face (in input order): the part that hands over a
    /// border vertex's own quadric.
    first: Vec<u32>,
    /// The input's quadric of each border vertex, by input id ([`border_quadrics`]).
    border_quadrics: FxHashMap<u32, Quadric>,
}

impl Partition {
    /// Cuts `mesh` into `parts` runs of the Morton curve of its face centroids, of face
    /// counts differing by at most one.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for no part, more parts than faces, or a mesh whose box
    /// [`UnitFrame`] refuses; [`Error::Topology`] for a mesh a build refuses.
    pub fn of(mesh: &Mesh, parts: usize) -> Result<Partition> {
        let faces = mesh.face_count();
        if parts == 0 || parts > faces {
            return Err(Error::InvalidInput(format!("{parts} parts of a mesh of {faces} faces: give 1 to {faces}")));
        }
        if faces > u32::MAX as usize {
            return Err(Error::InvalidInput(format!("{faces} faces exceed the 32-bit index range")));
        }
        mesh.check()?;
        let unit = UnitFrame::of(mesh)?;
        let owner = morton::morton_owners(&mesh.positions, &mesh.triangles, &unit, parts);
        Partition::grouped(mesh, owner, parts, unit)
    }

    /// The partition giving face f to part `owner[f]` (any cut: components, materials, a
    /// caller's own).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for an owner list of another length than the faces', or a
    /// part number of `parts` or more.
    pub fn with_owners(mesh: &Mesh, owner: Vec<u32>, parts: usize) -> Result<Partition> {
        if owner.len() != mesh.face_count() {
            return Err(Error::InvalidInput(format!("{} owners for {} faces", owner.len(), mesh.face_count())));
        }
        if let Some(f) = owner.iter().position(|&o| o as usize >= parts) {
            return Err(Error::InvalidInput(format!("face {f} is given part {} of {parts}", owner[f])));
        }
        mesh.check()?;
        Partition::grouped(mesh, owner, parts, UnitFrame::of(mesh)?)
    }

    /// The partition of a checked `mesh` by checked owners: its border vertices, and its
    /// faces grouped by part (a counting sort, so a part's faces keep their input order),
    /// the mesh checked as a build checks it (part by part: [`Partition::check_topology`]),
    /// and the border vertices' quadrics.
    ///
    /// # Errors
    /// [`Error::Topology`] for a mesh a build refuses; as [`border_quadrics`].
    fn grouped(mesh: &Mesh, owner: Vec<u32>, parts: usize, frame: UnitFrame) -> Result<Partition> {
        let mut first = vec![u32::MAX; mesh.vertex_count()];
        let mut border = vec![false; mesh.vertex_count()];
        let mut starts = vec![0usize; parts + 1];
        for (t, &part) in mesh.triangles.iter().zip(&owner) {
            starts[part as usize + 1] += 1;
            for &v in t {
                match first[v as usize] {
                    u32::MAX => first[v as usize] = part,
                    p if p != part => border[v as usize] = true,
                    _ => {}
                }
            }
        }
        for k in 0..parts {
            starts[k + 1] += starts[k];
        }
        let mut next = starts[..parts].to_vec();
        let mut faces = vec![0u32; owner.len()];
        for (f, &part) in owner.iter().enumerate() {
            faces[next[part as usize]] = f as u32;
            next[part as usize] += 1;
        }
        let mut partition =
            Partition { owner, parts, border, faces, starts, frame, first, border_quadrics: FxHashMap::default() };
        // A build's checks, before CGAL measures the border stars' quadrics.
        partition.check_topology(mesh)?;
        crate::hierarchy::simplify::check_faces_and_vertices(mesh, None)?;
        partition.border_quadrics = border_quadrics(mesh, &partition.border, &frame)?;
        Ok(partition)
    }

    /// Number of parts.
    pub fn parts(&self) -> usize {
        self.parts
    }

    /// The part of face `f`.
    pub fn owner(&self, f: usize) -> u32 {
        self.owner[f]
    }

    /// Whether input vertex `v` lies on faces of two parts or more.
    pub fn is_border(&self, v: u32) -> bool {
        self.border[v as usize]
    }

    /// Number of border vertices.
    pub fn border_count(&self) -> usize {
        self.border.iter().filter(|&&b| b).count()
    }

    /// Part `k` of `mesh` as a mesh of its own: its faces, the vertices they use (renumbered
    /// in order of first use), a vertex where the part's faces meet only at that vertex
    /// split into one copy per fan (a run of the curve may pinch there; every copy is a
    /// border vertex), and which of its vertices are border vertices.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a part number out of range.
    pub fn part(&self, mesh: &Mesh, k: usize) -> Result<Part> {
        if k >= self.parts {
            return Err(Error::InvalidInput(format!("part {k} of {} (0..{})", self.parts, self.parts - 1)));
        }
        // Local ids from a map the part's size: parts built side by side each touch only
        // their own faces and vertices.
        let own = self.own_faces(k);
        let (ids, triangles) = localised(own.iter().map(|&f| mesh.triangles[f as usize]), own.len());
        let positions = ids.iter().map(|&v| mesh.positions[v as usize]).collect();
        let mut part = Mesh::new(positions, triangles);
        part.uvs = mesh.uvs.as_ref().map(|uvs| part_uvs(uvs, own));
        part.materials = mesh.materials.as_ref().map(|m| part_materials(m, own));
        // The input ids ride along as a scalar, which the split copies to each copy.
        part.scalars.insert(INPUT_ID.to_string(), ids.iter().map(|&v| f64::from(v)).collect());
        split_non_manifold_fans(&mut part);
        let ids: Vec<u32> =
            part.scalars.remove(INPUT_ID).expect("the ids' scalar").into_iter().map(|v| v as u32).collect();
        let border: Vec<u32> = (0..ids.len() as u32).filter(|&v| self.border[ids[v as usize] as usize]).collect();
        // Each border vertex's own quadric goes with one part (its first face's) and one
        // copy there; the continuation sums what the parts hand over.
        let mut handed: FxHashSet<u32> = FxHashSet::default();
        let border_quadrics = border
            .iter()
            .map(|&b| {
                let v = ids[b as usize];
                match self.first[v as usize] == k as u32 && handed.insert(v) {
                    true => self.border_quadrics.get(&v).copied().unwrap_or_default(),
                    false => Quadric::default(),
                }
            })
            .collect();
        Ok(Part { mesh: part, ids, border, input_frame: self.frame, border_quadrics })
    }
}

impl Partition {
    /// Part k's faces, in input order.
    fn own_faces(&self, k: usize) -> &[u32] {
        &self.faces[self.starts[k]..self.starts[k + 1]]
    }

    /// Refuses a mesh that is not an oriented manifold, as a build does
    /// (`check_oriented_manifold` in `simplify.rs`), checked part by part: an
    /// edge with an end inside a part (not on its border) has all its faces in that part,
    /// and so has such a vertex; an edge between two border vertices, and a border vertex,
    /// has all its faces among the border vertices' stars. Each is counted once, where
    /// all its faces are, so the counts are the whole mesh's, and no table of the whole
    /// mesh's edges is made (48 bytes a face). Whether a mesh whose faces disagree could be
    /// oriented is not known here: its refusal says it is not an oriented manifold.
    ///
    /// # Errors
    /// [`Error::Topology`] with the counts.
    pub fn check_topology(&self, mesh: &Mesh) -> Result<()> {
        let mut counts = TopologyCounts::default();
        for k in 0..self.parts {
            let own = self.own_faces(k);
            let (ids, triangles) = localised(own.iter().map(|&f| mesh.triangles[f as usize]), own.len());
            let inside = |v: u32| !self.border[ids[v as usize] as usize];
            counts =
                counts.plus(TopologyCounts::of_piece(&triangles, ids.len(), inside, |a, b| inside(a) || inside(b)));
        }
        let (ids, triangles) = self.border_stars(mesh);
        let border = |v: u32| self.border[ids[v as usize] as usize];
        counts = counts.plus(TopologyCounts::of_piece(&triangles, ids.len(), border, |a, b| border(a) && border(b)));
        crate::hierarchy::simplify::check_oriented_manifold(&counts, None)
    }

    /// The faces at a border vertex, over their own vertices in order of first use, and
    /// each vertex's input id.
    fn border_stars(&self, mesh: &Mesh) -> (Vec<u32>, Vec<[u32; 3]>) {
        let stars = mesh.triangles.iter().filter(|t| t.iter().any(|&v| self.border[v as usize]));
        localised(stars.copied(), 0)
    }
}

/// `triangles` over their own vertices, numbered in order of first use, and each one's id
/// in `triangles`.
fn localised(triangles: impl Iterator<Item = [u32; 3]>, capacity: usize) -> (Vec<u32>, Vec<[u32; 3]>) {
    let mut local: FxHashMap<u32, u32> = FxHashMap::default();
    local.reserve(capacity);
    let mut ids: Vec<u32> = Vec::new();
    let mut out = Vec::with_capacity(capacity);
    for t in triangles {
        out.push(t.map(|v| {
            *local.entry(v).or_insert_with(|| {
                ids.push(v);
                ids.len() as u32 - 1
            })
        }));
    }
    (ids, out)
}

/// The corner UVs of the faces `own`, with the coordinates they use (in order of first
/// use): the part's seams are the input's.
fn part_uvs(uvs: &CornerUvs, own: &[u32]) -> CornerUvs {
    let mut local: FxHashMap<u32, u32> = FxHashMap::default();
    let mut values = Vec::new();
    let corners = own
        .iter()
        .map(|&f| {
            uvs.corners[f as usize].map(|i| {
                *local.entry(i).or_insert_with(|| {
                    values.push(uvs.values[i as usize]);
                    values.len() as u32 - 1
                })
            })
        })
        .collect();
    CornerUvs { values, corners }
}

/// The materials of the faces `own`, numbered in order of first use: which material each
/// face has, which is what finds the seams between materials. The names stay with the
/// input (a part's build writes none); a part's are its numbers.
fn part_materials(materials: &Materials, own: &[u32]) -> Materials {
    let mut local: FxHashMap<u32, u32> = FxHashMap::default();
    let faces = own
        .iter()
        .map(|&f| match materials.faces[f as usize] {
            u32::MAX => u32::MAX,
            m => {
                let next = local.len() as u32;
                *local.entry(m).or_insert(next)
            }
        })
        .collect();
    Materials { libraries: Vec::new(), names: (0..local.len()).map(|i| i.to_string()).collect(), faces }
}

/// The scalar that carries input ids through a part's fan split.
const INPUT_ID: &str = "\u{0}asperity-input-id";

/// One part of a [`Partition`] as a mesh of its own.
#[derive(Debug, Clone)]
pub struct Part {
    /// The part's faces over its own vertices.
    pub mesh: Mesh,
    /// The input id of each of the part's vertices.
    pub ids: Vec<u32>,
    /// The part's vertices on its border (to fence in its build).
    pub border: Vec<u32>,
    /// The input's unit frame: an error bound is a fraction of its diagonal, in every
    /// part (a part's own box is smaller), and the quadrics the part hands over are in it.
    pub input_frame: UnitFrame,
    /// The input's quadric of each border vertex (in `border`'s order) that this part
    /// hands over, zero where another part or another copy hands it over: a part sees only
    /// its side of a border vertex's star.
    pub border_quadrics: Vec<Quadric>,
}

impl Part {
    /// `triangles` over the part's vertices (its base domain's) in input ids.
    pub fn input_triangles(&self, triangles: &[[u32; 3]]) -> Vec<[u32; 3]> {
        triangles.iter().map(|t| t.map(|v| self.ids[v as usize])).collect()
    }
}

/// The input's quadric of each border vertex (`vertex_quadrics` in the input's unit
/// frame, with a build's boundary weight), computed on the border vertices' stars alone: a
/// border vertex's star is whole there, and an edge at it is a boundary there only where it
/// is the input's, so its quadric is the one a build of the whole input starts from. A
/// vertex of the stars' outer rim where they meet only at it is split into one copy per
/// fan, which leaves the border vertices' stars as they are.
///
/// # Errors
/// As [`crate::ffi::vertex_quadrics`].
fn border_quadrics(mesh: &Mesh, border: &[bool], frame: &UnitFrame) -> Result<FxHashMap<u32, Quadric>> {
    let stars = mesh.triangles.iter().filter(|t| t.iter().any(|&v| border[v as usize]));
    let (ids, triangles) = localised(stars.copied(), 0);
    if triangles.is_empty() {
        return Ok(FxHashMap::default());
    }
    let positions = ids.iter().map(|&v| frame.to_unit(mesh.positions[v as usize])).collect();
    let mut stars = Mesh::new(positions, triangles);
    stars.scalars.insert(INPUT_ID.to_string(), ids.iter().map(|&v| f64::from(v)).collect());
    split_non_manifold_fans(&mut stars);
    let ids = stars.scalars.remove(INPUT_ID).expect("the ids' scalar");
    let quadrics = crate::ffi::vertex_quadrics(&stars, BOUNDARY_WEIGHT)?;
    Ok(ids.into_iter().zip(quadrics).map(|(v, q)| (v as u32, q)).filter(|&(v, _)| border[v as usize]).collect())
}
