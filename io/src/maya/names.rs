//! Node names: Maya DAG node names are unique only among siblings, so a file refers to a
//! node by its short name when that is unique and by a `|`-separated DAG path otherwise
//! (`|group|base|baseShape`). [`NameIndex`] resolves parents in file order and any name or
//! path written in a connection, and chooses the sinew name of each node: its short name
//! when unique, else its path with `|` turned into `_` (rig names cannot contain `|`).

use std::collections::HashMap;

use super::plug::short_name;
use super::scene::MaScene;

/// Resolved names of a scene's nodes.
#[derive(Clone, Debug, Default)]
pub struct NameIndex {
    /// Full DAG path (`|a|b`) of each node; non-DAG (unparented, never a parent) nodes have
    /// `|name` too, which never clashes with how files name them.
    pub paths: Vec<String>,
    /// Nodes by short name.
    by_leaf: HashMap<String, Vec<usize>>,
}

impl NameIndex {
    /// Resolves every node's parent (setting `parent_index`) and builds the index. Returns
    /// the parents that name no node, as `(node index, written parent)`.
    pub fn build(scene: &mut MaScene) -> (NameIndex, Vec<(usize, String)>) {
        let mut idx = NameIndex::default();
        let mut missing = Vec::new();
        for (i, n) in scene.nodes.iter().enumerate() {
            idx.by_leaf.entry(short_name(&n.name).to_string()).or_default().push(i);
        }
        idx.paths = vec![String::new(); scene.nodes.len()];
        let mut parents = vec![None; scene.nodes.len()];
        #[allow(clippy::needless_range_loop)] // `i` also indexes `idx.paths` and `scene.nodes`
        for i in 0..scene.nodes.len() {
            let written = scene.nodes[i].parent.clone();
            let parent = written.as_deref().and_then(|p| {
                idx.resolve_before(p, i)
                    .or_else(|| idx.resolve(p).ok().flatten())
                    .filter(|&q| q != i)
            });
            if let (Some(w), None) = (&written, parent) {
                missing.push((i, w.clone()));
            }
            parents[i] = parent;
            let leaf = short_name(&scene.nodes[i].name);
            idx.paths[i] = match parent {
                Some(p) if !idx.paths[p].is_empty() => format!("{}|{leaf}", idx.paths[p]),
                _ => format!("|{leaf}"),
            };
        }
        // A `parent` command may have put a node under a later one: recompute every path
        // from the final parents (a parent loop, which Maya cannot write, stops the walk).
        for i in 0..scene.nodes.len() {
            let mut parts = vec![short_name(&scene.nodes[i].name)];
            let mut at = parents[i];
            while let Some(p) = at {
                if parts.len() > scene.nodes.len() {
                    break;
                }
                parts.push(short_name(&scene.nodes[p].name));
                at = parents[p];
            }
            parts.reverse();
            idx.paths[i] = format!("|{}", parts.join("|"));
        }
        for (n, p) in scene.nodes.iter_mut().zip(&parents) {
            n.parent_index = *p;
        }
        (idx, missing)
    }

    fn matches(&self, i: usize, written: &str) -> bool {
        let w = written.strip_prefix(':').unwrap_or(written);
        if w.starts_with('|') {
            self.paths[i] == w
        } else if w.contains('|') {
            self.paths[i].ends_with(&format!("|{w}"))
        } else {
            true
        }
    }

    /// The node a name written before node `before` refers to (only earlier nodes count).
    fn resolve_before(&self, written: &str, before: usize) -> Option<usize> {
        let c = self.by_leaf.get(short_name(written))?;
        // The latest earlier node with that name (the one Maya's name lookup saw then).
        c.iter()
            .copied()
            .rev()
            .find(|&i| i < before && self.matches(i, written))
    }

    /// The node a written name or path refers to: `Ok(None)` when no node has it,
    /// `Err(candidates)` when a short name is ambiguous.
    pub fn resolve(&self, written: &str) -> Result<Option<usize>, Vec<String>> {
        let Some(c) = self.by_leaf.get(short_name(written)) else {
            return Ok(None);
        };
        let hits: Vec<usize> = c.iter().copied().filter(|&i| self.matches(i, written)).collect();
        match hits.as_slice() {
            [] => Ok(None),
            [one] => Ok(Some(*one)),
            many => Err(many.iter().map(|&i| self.paths[i].clone()).collect()),
        }
    }

    /// Whether node `i`'s short name is shared with another node.
    pub fn ambiguous(&self, i: usize) -> bool {
        self.paths
            .get(i)
            .and_then(|p| self.by_leaf.get(short_name(p)))
            .is_some_and(|c| c.len() > 1)
    }

    /// The name sinew uses for node `i` before uniquifying: the short name when unique, else
    /// the DAG path without its leading `|` and with `|` as `_`.
    pub fn sinew_name(&self, scene: &MaScene, i: usize) -> String {
        let leaf = short_name(&scene.nodes[i].name).to_string();
        if self.ambiguous(i) {
            self.paths[i].trim_start_matches('|').replace('|', "_")
        } else {
            leaf
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::maya::parse::parse;

    #[test]
    fn duplicate_short_names_resolve_by_path() {
        let src = r#"
createNode transform -n "a";
createNode transform -n "base" -p "a";
createNode mesh -n "shape" -p "|a|base";
createNode transform -n "b";
createNode transform -n "base" -p "b";
createNode mesh -n "shape" -p "|b|base";
createNode joint -n "j";
"#;
        let mut scene = parse(src).unwrap();
        let (idx, missing) = NameIndex::build(&mut scene);
        assert!(missing.is_empty());
        assert_eq!(idx.paths[2], "|a|base|shape");
        assert_eq!(idx.paths[5], "|b|base|shape");
        assert_eq!(scene.nodes[5].parent_index, Some(4));
        assert_eq!(idx.resolve("|b|base|shape"), Ok(Some(5)));
        assert_eq!(idx.resolve("b|base"), Ok(Some(4)));
        assert_eq!(idx.resolve("j"), Ok(Some(6)));
        assert_eq!(idx.resolve(":j"), Ok(Some(6)));
        assert_eq!(idx.resolve("nope"), Ok(None));
        assert!(idx.resolve("base").is_err());
        assert_eq!(idx.sinew_name(&scene, 4), "b_base");
        assert_eq!(idx.sinew_name(&scene, 6), "j");
    }
}
