//! The dependency graph as SVG, laid out by the `layout-rs` crate (a Sugiyama-style
//! layered layout, the way Graphviz's `dot` draws, in pure Rust): the whole graph
//! (`sinew graph --svg`) or the nodes around one (the viewer's graph panel, upstream and
//! downstream a few levels). Each node is a box with its name and type, carrying
//! `data-node="name"` so a page can make it clickable; each edge is labelled with the
//! plugs it connects. Profiled nodes are shaded by their share of the frame, nodes with
//! evaluation errors are outlined in red.

use std::collections::{BTreeMap, HashMap, HashSet, VecDeque};

use layout::backends::svg::SVGWriter;
use layout::core::base::Orientation;
use layout::core::color::Color;
use layout::core::geometry::Point;
use layout::core::style::StyleAttr;
use layout::std_shapes::shapes::{Arrow, Element, ShapeKind};
use layout::topo::layout::VisualGraph;
use sinew_core::{Graph, NodeId, ProfileTable};

/// Most nodes drawn around a center (the nearest levels first).
pub const MAX_NEIGHBORHOOD: usize = 80;

/// What to draw and how to mark it.
#[derive(Clone, Copy, Debug, Default)]
pub struct SvgOptions<'a> {
    /// Draw only the nodes around this one (`None`: the whole graph).
    pub center: Option<&'a str>,
    /// Levels upstream and downstream of the center.
    pub depth: usize,
    /// Shade nodes by their share of the profiled frame.
    pub profile: Option<&'a ProfileTable>,
    /// Nodes with evaluation errors.
    pub errors: &'a [&'a str],
}

/// The node-level edges of `graph`: for each (source node, destination node), the plug
/// pairs (`srcAttr`, `dstAttr`) that connect them.
fn node_edges(graph: &Graph) -> BTreeMap<(NodeId, NodeId), Vec<(String, String)>> {
    let mut edges: BTreeMap<(NodeId, NodeId), Vec<(String, String)>> = BTreeMap::new();
    for (s, d) in graph.connections() {
        let attr = |p: sinew_core::Plug| {
            let name = graph.plug_name(p);
            name.split_once('.').map(|(_, a)| a.to_string()).unwrap_or(name)
        };
        edges.entry((s.node, d.node)).or_default().push((attr(s), attr(d)));
    }
    edges
}

/// The nodes within `depth` connections of `center`, upstream and downstream, nearest
/// first, at most [`MAX_NEIGHBORHOOD`].
fn neighborhood(
    center: NodeId,
    depth: usize,
    edges: &BTreeMap<(NodeId, NodeId), Vec<(String, String)>>,
) -> HashSet<NodeId> {
    let mut up: HashMap<NodeId, Vec<NodeId>> = HashMap::new();
    let mut down: HashMap<NodeId, Vec<NodeId>> = HashMap::new();
    for &(s, d) in edges.keys() {
        down.entry(s).or_default().push(d);
        up.entry(d).or_default().push(s);
    }
    let mut seen = HashSet::from([center]);
    for dir in [&up, &down] {
        let mut queue = VecDeque::from([(center, 0)]);
        while let Some((n, level)) = queue.pop_front() {
            if level == depth {
                continue;
            }
            for &m in dir.get(&n).into_iter().flatten() {
                if seen.len() >= MAX_NEIGHBORHOOD {
                    return seen;
                }
                if seen.insert(m) {
                    queue.push_back((m, level + 1));
                }
            }
        }
    }
    seen
}

fn escape_attr(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Renders the graph (or the part around `opts.center`) as an SVG document.
pub fn render(graph: &Graph, opts: &SvgOptions<'_>) -> Result<String, String> {
    let edges = node_edges(graph);
    let chosen: Vec<NodeId> = match opts.center {
        Some(name) => {
            let c = graph.node_id(name).map_err(|e| e.to_string())?;
            let near = neighborhood(c, opts.depth, &edges);
            graph.nodes().into_iter().filter(|n| near.contains(n)).collect()
        }
        None => graph.nodes(),
    };
    let cost: HashMap<&str, f64> = opts
        .profile
        .map(|t| t.nodes.iter().map(|r| (r.name.as_str(), t.share(r))).collect())
        .unwrap_or_default();
    let max_cost = cost.values().copied().fold(0.0, f64::max);
    let mut vg = VisualGraph::new(Orientation::LeftToRight);
    let mut handles = HashMap::new();
    for &id in &chosen {
        let name = graph.node_name(id).unwrap_or_default();
        let ty = graph.node_type(id).unwrap_or_default();
        let mut label = format!("{name}\n{ty}");
        let mut look = StyleAttr::simple();
        look.font_size = 13;
        look.line_width = 1;
        look.rounded = 4;
        let mut class = "node".to_string();
        if let Some(&share) = cost.get(name) {
            label.push_str(&format!("\n{:.1}%", share * 100.0));
            // White to orange by share of the costliest node.
            let k = if max_cost > 0.0 { share / max_cost } else { 0.0 };
            let g = (255.0 - 120.0 * k) as u32;
            let b = (255.0 - 230.0 * k) as u32;
            look.fill_color = Some(Color::new((0xff << 24) | (g << 16) | (b << 8) | 0xff));
            if k > 0.5 {
                class.push_str(" costly");
            }
        }
        if opts.errors.contains(&name) {
            look.line_color = Color::fast("red");
            look.line_width = 3;
            class.push_str(" error");
        }
        if opts.center == Some(name) {
            look.line_color = Color::fast("blue");
            look.line_width = 3;
            class.push_str(" center");
        }
        let props = format!("class=\"{class}\" data-node=\"{}\"", escape_attr(name));
        let shape = ShapeKind::new_box(&label);
        let elem = Element::create_with_properties(shape, look, Orientation::LeftToRight, Point::new(100., 40.), props);
        handles.insert(id, vg.add_node(elem));
    }
    for ((s, d), plugs) in &edges {
        let (Some(&hs), Some(&hd)) = (handles.get(s), handles.get(d)) else {
            continue;
        };
        if s == d {
            continue;
        }
        let mut lines: Vec<String> = plugs.iter().take(3).map(|(a, b)| format!("{a} → {b}")).collect();
        if plugs.len() > 3 {
            lines.push(format!("+{} more", plugs.len() - 3));
        }
        let mut arrow = Arrow::simple(&lines.join("\n"));
        arrow.look.font_size = 10;
        arrow.look.line_width = 1;
        vg.add_edge(arrow, hs, hd);
    }
    if vg.num_nodes() == 0 {
        return Ok("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\"></svg>".into());
    }
    let mut svg = SVGWriter::new();
    // Crossing reduction is quadratic-ish in layout-rs: skip it on big graphs (hundreds of
    // nodes take minutes with it, a second without).
    vg.do_it(false, vg.num_nodes() > 150, false, &mut svg);
    Ok(svg.finalize())
}

/// A standalone HTML page showing the SVG with pan, zoom and a node search (for
/// `sinew graph --html`: no Graphviz and no network needed to open it).
pub fn html_page(title: &str, svg: &str) -> String {
    include_str!("../assets/graph_page.html")
        .replace("{{TITLE}}", &escape_attr(title))
        .replace("{{SVG}}", svg)
}
