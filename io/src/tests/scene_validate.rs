//! `Scene::validate` on large and broken hierarchies (#22): linear in the links, so a
//! 100,000-deep chain or a node with 100,000 children validates at once (each walked the
//! whole chain or list before: 5·10^9 steps), and every inconsistency is still named.

use crate::scene::{Node, Scene};

fn scene(nodes: Vec<Node>) -> Scene {
    Scene {
        roots: (0..nodes.len()).filter(|&i| nodes[i].parent.is_none()).collect(),
        nodes,
        meshes: Vec::new(),
        skins: Vec::new(),
        animations: Vec::new(),
        warnings: Vec::new(),
    }
}

/// `n` nodes where node `i` has parent `parent(i)`, children listed to match.
fn hierarchy(n: usize, parent: impl Fn(usize) -> Option<usize>) -> Vec<Node> {
    let mut nodes: Vec<Node> = (0..n)
        .map(|i| Node {
            parent: parent(i),
            ..Node::default()
        })
        .collect();
    for i in 0..n {
        if let Some(p) = nodes[i].parent {
            nodes[p].children.push(i);
        }
    }
    nodes
}

#[test]
fn a_100000_deep_chain_and_a_100000_child_star_validate() {
    let n = 100_000;
    let chain = scene(hierarchy(n, |i| i.checked_sub(1)));
    assert_eq!(chain.validate(), Ok(()));
    let star = scene(hierarchy(n, |i| (i > 0).then_some(0)));
    assert_eq!(star.validate(), Ok(()));
}

#[test]
fn inconsistent_links_and_cycles_are_named() {
    // A cycle 1 -> 2 -> 3 -> 1 below nothing (node 0 is a root).
    let mut nodes = hierarchy(4, |i| [None, Some(3), Some(1), Some(2)][i]);
    let err = scene(nodes.clone()).validate().unwrap_err();
    assert!(err.contains("its own ancestor"), "{err}");
    // A child listed twice.
    nodes = hierarchy(3, |i| i.checked_sub(1));
    nodes[0].children.push(1);
    assert_eq!(scene(nodes).validate(), Err("node 0: lists child 1 twice".into()));
    // A parent that does not list its child.
    nodes = hierarchy(3, |i| i.checked_sub(1));
    nodes[1].children.clear();
    assert_eq!(
        scene(nodes).validate(),
        Err("node 2: parent 1 does not list it as a child".into())
    );
    // A child that names another parent.
    nodes = hierarchy(3, |i| i.checked_sub(1));
    nodes[0].children.push(2);
    assert_eq!(
        scene(nodes).validate(),
        Err("node 0: child 2 does not have it as parent".into())
    );
}
