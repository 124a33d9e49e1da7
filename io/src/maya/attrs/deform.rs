//! Attribute tables of geometry and deformer types: `mesh`, the poly creation nodes,
//! `geometryFilter` and its deformers (`skinCluster`, `blendShape`, `tweak`), the set
//! plumbing (`groupParts`, `groupId`, `objectSet`) and `dagPose`.

use super::Table;
use crate::maya::units::UnitClass::{Linear as L, None as N};

const MESH: Table = &[
    ("inMesh", "i", N),
    ("outMesh", "o", N),
    ("worldMesh", "w", N),
    ("cachedInMesh", "ci", N),
    ("pnts", "pt", L),
    ("pntx", "px", L),
    ("pnty", "py", L),
    ("pntz", "pz", L),
    ("vrts", "vt", L),
    ("edge", "ed", N),
    ("face", "fc", N),
    ("normals", "n", N),
    ("uvSet", "uvst", N),
    ("uvSetName", "uvsn", N),
    ("uvSetPoints", "uvsp", N),
    ("currentUVSet", "cuvs", N),
    ("tweakLocation", "twl", N),
    ("displayColors", "dcol", N),
    ("displayColorChannel", "dcc", N),
];

const POLY_PLANE: Table = &[
    ("output", "out", N),
    ("width", "w", L),
    ("height", "h", L),
    ("subdivisionsWidth", "sw", N),
    ("subdivisionsHeight", "sh", N),
    ("axis", "ax", N),
    ("createUVs", "cuv", N),
];

const POLY_CUBE: Table = &[
    ("output", "out", N),
    ("width", "w", L),
    ("height", "h", L),
    ("depth", "d", L),
    ("subdivisionsWidth", "sw", N),
    ("subdivisionsHeight", "sh", N),
    ("subdivisionsDepth", "sd", N),
    ("axis", "ax", N),
    ("createUVs", "cuv", N),
];

const GEOMETRY_FILTER: Table = &[
    ("envelope", "en", N),
    ("input", "ip", N),
    ("inputGeometry", "ig", N),
    ("groupId", "gi", N),
    ("outputGeometry", "og", N),
    ("originalGeometry", "orggeom", N),
    ("function", "fn", N),
    ("fchild1", "fc1", N),
];

const WEIGHT_GEOMETRY_FILTER: Table = &[("weightList", "wl", N), ("weights", "w", N)];

/// `cluster` (Maya's node reference, *cluster*): `clusterXforms` is the compound the
/// `clusterHandle` shape feeds.
const CLUSTER: Table = &[
    ("percentResolution", "ptr", N),
    ("usePartialResolution", "upr", N),
    ("relative", "rel", N),
    ("clusterXforms", "x", N),
    ("preMatrix", "pre", N),
    ("weightedMatrix", "wt", N),
    ("postMatrix", "post", N),
    ("weightedCompensationMatrix", "wcm", N),
    ("geomMatrix", "gm", N),
    ("matrix", "ma", N),
    ("bindPreMatrix", "pm", N),
    ("bindState", "bs", N),
    ("postCompensationMatrix", "psc", N),
    ("preCompensationMatrix", "prc", N),
    ("angleInterpolation", "ait", N),
];

const SKIN_CLUSTER: Table = &[
    ("weightList", "wl", N),
    ("weights", "w", N),
    ("bindPreMatrix", "pm", N),
    ("geomMatrix", "gm", N),
    ("matrix", "ma", N),
    ("dropoff", "dpf", N),
    ("smoothness", "smt", N),
    ("lockWeights", "lw", N),
    ("maintainMaxInfluences", "mmi", N),
    ("maxInfluences", "mi", N),
    ("bindMethod", "bm", N),
    ("paintWeights", "ptw", N),
    ("useComponents", "uc", N),
    ("nurbsSamples", "ns", N),
    ("useComponentsMatrix", "ucm", N),
    ("normalizeWeights", "nw", N),
    ("deformUserNormals", "dun", N),
    ("weightDistribution", "wd", N),
    ("skinningMethod", "skm", N),
    ("dqsSupportNonRigid", "dqsi", N),
    ("dqsScale", "dqs", N),
    ("blendWeights", "bw", N),
    ("influenceColor", "ifcl", N),
    ("bindPose", "bp", N),
    ("bindVolume", "bv", N),
    ("heatmapFalloff", "hmf", N),
];

const BLEND_SHAPE: Table = &[
    ("weight", "w", N),
    ("inputTarget", "it", N),
    ("inputTargetGroup", "itg", N),
    ("inputTargetItem", "iti", N),
    ("inputGeomTarget", "igt", N),
    ("inputPointsTarget", "ipt", L),
    ("inputComponentsTarget", "ict", N),
    ("inputRelativePointsTarget", "irp", L),
    ("inputRelativeComponentsTarget", "irc", N),
    ("targetWeights", "tw", N),
    ("normalizationId", "nid", N),
    ("postDeformersMode", "pdm", N),
    ("baseWeights", "bw", N),
    ("paintTargetWeights", "pwt", N),
    ("origin", "or", N),
    ("baseOrigin", "bo", L),
    ("targetOrigin", "to", L),
    ("inbetweenInfoGroup", "ibig", N),
    ("inbetweenInfo", "ibi", N),
    ("inbetweenTargetName", "ibtn", N),
    ("interpolationCurve", "itc", N),
    ("targetDirectory", "tgdt", N),
    ("directoryWeight", "dwgh", N),
    ("childIndices", "cid", N),
    ("attributeAliasList", "aal", N),
    ("topologyCheck", "tc", N),
    ("supportNegativeWeights", "snw", N),
    ("offsetX", "ofx", L),
    ("offsetY", "ofy", L),
    ("offsetZ", "ofz", L),
    ("targetMatrix", "tmx", N),
    ("targetBindMatrix", "bmx", N),
    ("midLayerId", "mlid", N),
    ("midLayerParent", "mlpr", N),
];

const TWEAK: Table = &[
    ("relativeTweak", "rtw", N),
    ("vlist", "vl", N),
    ("vertex", "vt", L),
    ("xVertex", "vx", L),
    ("yVertex", "vy", L),
    ("zVertex", "vz", L),
    ("plist", "pl", N),
    ("controlPoints", "cp", L),
];

const GROUP_PARTS: Table = &[
    ("inputGeometry", "ig", N),
    ("outputGeometry", "og", N),
    ("groupId", "gi", N),
    ("inputComponents", "ic", N),
    ("inputRemoveComponent", "irc", N),
];

const GROUP_ID: Table = &[("groupId", "id", N)];

const OBJECT_SET: Table = &[
    ("dagSetMembers", "dsm", N),
    ("dnSetMembers", "dnsm", N),
    ("memberWireframeColor", "mwc", N),
    ("groupNodes", "gn", N),
    ("usedBy", "ub", N),
    ("verticesOnlySet", "vo", N),
];

const DAG_POSE: Table = &[
    ("members", "m", N),
    ("worldMatrix", "wm", N),
    ("xformMatrix", "xm", N),
    ("parents", "p", N),
    ("world", "w", N),
    ("bindPose", "bp", N),
    ("global", "g", N),
];

/// `(type, parent, own attributes)` of the geometry and deformer types.
pub(super) const TYPES: &[(&str, Option<&str>, Table)] = &[
    ("mesh", Some("shape"), MESH),
    ("polyPlane", Some("node"), POLY_PLANE),
    ("polyCube", Some("node"), POLY_CUBE),
    ("geometryFilter", Some("node"), GEOMETRY_FILTER),
    ("weightGeometryFilter", Some("geometryFilter"), WEIGHT_GEOMETRY_FILTER),
    ("skinCluster", Some("geometryFilter"), SKIN_CLUSTER),
    ("blendShape", Some("geometryFilter"), BLEND_SHAPE),
    ("tweak", Some("geometryFilter"), TWEAK),
    (
        "nonLinear",
        Some("weightGeometryFilter"),
        &[("matrix", "ma", N), ("deformerData", "dd", N)],
    ),
    ("cluster", Some("weightGeometryFilter"), CLUSTER),
    ("ffd", Some("weightGeometryFilter"), &[]),
    ("wire", Some("weightGeometryFilter"), &[]),
    ("deltaMush", Some("weightGeometryFilter"), &[]),
    ("groupParts", Some("node"), GROUP_PARTS),
    ("groupId", Some("node"), GROUP_ID),
    ("objectSet", Some("node"), OBJECT_SET),
    ("dagPose", Some("node"), DAG_POSE),
];
