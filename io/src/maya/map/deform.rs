//! Maya's deformer plumbing, walked and folded.
//!
//! From a shape's `inMesh` the walk goes upstream: a deformer's
//! `outputGeometry[k]` leads to its `input[k].inputGeometry`, a `groupParts` to its
//! `inputGeometry`, until a mesh (the `*Orig` intermediate object) or a creation node. The
//! `groupId` nodes, the deformer sets (`objectSet`) and the `tweak` node carry no
//! deformation of their own once the tweak's offsets are added to the base points, so
//! they are folded; every connection among the chain's nodes is consumed.
//!
//! Membership: a `groupParts` lists the components a deformer acts on
//! (`inputComponents`, usually `vtx[*]`). sinew's deformers act on every vertex; a
//! partial membership is reported.

use std::collections::HashSet;

use super::meshdata::{add_offsets, PolyMesh};
use super::{Importer, Status};
use crate::maya::attrs;

/// What a chain starts from.
#[derive(Clone, Debug, PartialEq)]
pub enum Base {
    /// The shape's own data (no input).
    Own,
    /// A mesh (usually the intermediate `*Orig`).
    Mesh(usize),
    /// A creation node (`polyCube`...).
    Creator(usize),
    /// Something the importer cannot read, with why.
    Unsupported(usize, String),
}

/// A shape's deformer chain.
#[derive(Clone, Debug)]
pub struct Chain {
    /// Where the geometry comes from.
    pub base: Base,
    /// Deformers in the order they apply (first applied first).
    pub deformers: Vec<usize>,
    /// Plumbing nodes to fold.
    pub folded: Vec<usize>,
    /// Connections among the chain's nodes.
    pub conns: Vec<usize>,
    /// `(deformer, groupParts)`: the groupParts that selects what each deformer acts on.
    pub parts: Vec<(usize, usize)>,
}

/// Walks upstream from `shape` (see the module docs).
pub fn walk_chain(imp: &mut Importer, shape: usize) -> Chain {
    let mut chain = Chain {
        base: Base::Own,
        deformers: Vec::new(),
        folded: Vec::new(),
        conns: Vec::new(),
        parts: Vec::new(),
    };
    let mut members: HashSet<usize> = HashSet::from([shape]);
    let mut at = imp.input_conn(shape, "inMesh");
    let mut guard = 0;
    while let Some((c, src, path)) = at.take() {
        guard += 1;
        if guard > 256 {
            break;
        }
        chain.conns.push(c);
        members.insert(src);
        let ty = imp.node(src).ty.clone();
        if ty == "mesh" {
            chain.base = Base::Mesh(src);
            break;
        }
        if ty.starts_with("poly") {
            chain.base = Base::Creator(src);
            break;
        }
        if ty == "groupParts" {
            chain.folded.push(src);
            if let Some(&d) = chain.deformers.last() {
                if !chain.parts.iter().any(|(x, _)| *x == d) {
                    chain.parts.push((d, src));
                }
            }
            at = imp.input_conn(src, "inputGeometry");
            if at.is_none() {
                chain.base = Base::Unsupported(src, "a groupParts with no input".into());
            }
            continue;
        }
        let k = output_index(&path);
        if attrs::is_a(&ty, "geometryFilter") || k.is_some() {
            chain.deformers.push(src);
            let k = k.unwrap_or(0);
            at = imp.input_conn(src, &format!("input[{k}].inputGeometry"));
            if at.is_none() {
                chain.base = Base::Unsupported(src, format!("deformer {} has no input geometry", imp.node(src).name));
            }
            continue;
        }
        chain.base = Base::Unsupported(
            src,
            format!("a {ty} node, which is not a mesh, a creation node or a deformer"),
        );
        break;
    }
    chain.deformers.reverse();
    // Plumbing attached to the chain's deformers: group ids and deformer sets.
    let mut extra = Vec::new();
    for &d in chain.deformers.iter().chain(&chain.folded) {
        for c in imp.conns_into(d).into_iter().chain(imp.conns_from(d)) {
            let (s, t) = imp.ends[c];
            for n in [s, t].into_iter().flatten() {
                if matches!(imp.node(n).ty.as_str(), "groupId" | "objectSet") {
                    extra.push(n);
                }
            }
        }
    }
    for n in extra {
        if members.insert(n) {
            chain.folded.push(n);
        }
    }
    for &d in &chain.deformers {
        members.insert(d);
        if imp.node(d).ty == "tweak" {
            chain.folded.push(d);
        }
    }
    if let Base::Mesh(m) = chain.base {
        members.insert(m);
    }
    for &m in &members.clone() {
        for c in imp.conns_from(m) {
            if imp.ends[c].1.is_some_and(|t| members.contains(&t)) && !chain.conns.contains(&c) {
                chain.conns.push(c);
            }
        }
    }
    chain
}

/// `k` of a deformer output path `outputGeometry[k]`.
fn output_index(path: &str) -> Option<u32> {
    let rest = path.strip_prefix("outputGeometry")?;
    if rest.is_empty() {
        return Some(0);
    }
    rest.strip_prefix('[')?.strip_suffix(']')?.parse().ok()
}

/// The vertices deformer `d` acts on (its groupParts' `inputComponents`); `None` for every
/// vertex.
pub fn membership(imp: &Importer, chain: &Chain, d: usize) -> Option<Vec<i64>> {
    let (_, gp) = chain.parts.iter().find(|(x, _)| *x == d)?;
    let a = imp.set_attr(*gp, "inputComponents")?;
    let list = imp.values(a).component_list().ok()?;
    if list.is_empty() || list.iter().any(|c| c.first.is_none()) {
        return None;
    }
    let mut v: Vec<i64> = list
        .iter()
        .filter(|c| c.kind == "vtx")
        .flat_map(|c| i64::from(c.first.unwrap_or(0))..=i64::from(c.last.unwrap_or(0)))
        .collect();
    v.sort_unstable();
    v.dedup();
    Some(v)
}

/// Adds the offsets of the chain's first `tweak` node (`vlist[0].vertex[k]`) to the base
/// points; a tweak later in the chain with non-zero offsets is reported.
pub fn fold_tweaks(imp: &mut Importer, chain: &Chain, poly: &mut PolyMesh) {
    for (pos, &d) in chain.deformers.iter().enumerate() {
        if imp.node(d).ty != "tweak" {
            continue;
        }
        let mut offsets = Vec::new();
        for a in &imp.node(d).attrs {
            let segs = super::plugs::long_segs(imp, d, &a.segs);
            let ok = segs.len() == 2 && segs[0].name == "vlist" && segs[1].name == "vertex";
            let Some(idx) = segs.get(1).and_then(|s| s.index).filter(|_| ok && !a.values.is_empty()) else {
                continue;
            };
            let Some((x, y)) = idx.bounds() else {
                continue;
            };
            if let Ok(v) = imp.values(a).elements((y - x + 1) as usize, 3) {
                for (k, c) in v.chunks(3).enumerate() {
                    offsets.push((x + k as u32, glam::DVec3::new(c[0], c[1], c[2])));
                }
            }
        }
        let first = chain.deformers[..pos].iter().all(|&p| imp.node(p).ty == "tweak");
        if first {
            add_offsets(&mut poly.points, &offsets);
        } else if offsets.iter().any(|(_, o)| *o != glam::DVec3::ZERO) {
            let msg = format!(
                "tweak {} sits after other deformers; its offsets are not imported",
                imp.node(d).name
            );
            imp.warn(imp.node(d).at, msg);
        }
        if !imp.handled(d) {
            imp.set_status(d, Status::Folded);
        }
    }
}
