//! `docs/nodes.md` is generated from the registered specs (`sinew nodes
//! --markdown`): this test fails when the committed file is stale, and checks
//! that the registry covers every Maya node type issue #19 names.

use std::path::Path;

#[test]
fn docs_nodes_md_is_up_to_date() {
    let registry = sinew::default_registry().expect("registry");
    let want = sinew::cli::nodes_markdown(&registry);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/nodes.md");
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    if have != want {
        let line = have
            .lines()
            .zip(want.lines())
            .position(|(a, b)| a != b)
            .map_or(have.lines().count().min(want.lines().count()) + 1, |i| i + 1);
        panic!(
            "docs/nodes.md is stale (first difference at line {line}); regenerate it with `{}`",
            sinew::cli::MARKDOWN_COMMAND
        );
    }
}

#[test]
fn registry_covers_the_maya_utility_nodes() {
    let registry = sinew::default_registry().expect("registry");
    let math = [
        "sum",
        "subtract",
        "multiply",
        "divide",
        "power",
        "log",
        "modulo",
        "absolute",
        "negate",
        "min",
        "max",
        "average",
        "clampRange",
        "smoothStep",
        "lerp",
        "inverseLerp",
        "floor",
        "ceil",
        "round",
        "truncate",
        "sin",
        "cos",
        "tan",
        "asin",
        "acos",
        "atan",
        "atan2",
        "equal",
        "greaterThan",
        "lessThan",
        "crossProduct",
        "dotProduct",
        "normalize",
        "length",
        "rotateVector",
        "multiplyPointByMatrix",
        "multiplyVectorByMatrix",
    ];
    let mut names: Vec<String> = math.iter().map(|n| n.to_string()).collect();
    names.extend(math.iter().map(|n| format!("{n}DL")));
    names.extend(
        [
            "and",
            "or",
            "not",
            "wtAddMatrix",
            "addMatrix",
            "holdMatrix",
            "transposeMatrix",
            "aimMatrix",
            "blendMatrix",
            "pickMatrix",
            "quatSlerp",
            "quatProd",
            "quatInvert",
            "quatNormalize",
            "quatAdd",
            "quatSub",
            "quatNegate",
            "quatConjugate",
            "quatToAxisAngle",
            "axisAngleToQuat",
            "eulerToQuat",
            "quatToEuler",
            "angleBetween",
            "vectorProduct",
            "blendTwoAttr",
            "choice",
            "animBlendNodeAdditive",
            "animBlendNodeAdditiveDA",
            "animBlendNodeAdditiveDL",
            "animBlendNodeAdditiveF",
            "animBlendNodeAdditiveFA",
            "animBlendNodeAdditiveFL",
            "animBlendNodeAdditiveRotation",
            "pairBlend",
        ]
        .iter()
        .map(|n| n.to_string()),
    );
    let missing: Vec<&String> = names.iter().filter(|n| registry.spec(n).is_none()).collect();
    assert!(missing.is_empty(), "missing node types: {missing:?}");
}

#[test]
fn registry_covers_the_curve_surface_and_constraint_nodes() {
    let registry = sinew::default_registry().expect("registry");
    let names = [
        "nurbsCurve",
        "nurbsSurface",
        "curveInfo",
        "pointOnCurveInfo",
        "nearestPointOnCurve",
        "motionPath",
        "pointOnSurfaceInfo",
        "closestPointOnSurface",
        "follicle",
        "uvPin",
        "proximityPin",
        "pointOnPolyConstraint",
        "geometryConstraint",
        "normalConstraint",
        "tangentConstraint",
        "poleVectorConstraint",
        "ikRP",
        "ikSpring",
    ];
    let missing: Vec<&&str> = names.iter().filter(|n| registry.spec(n).is_none()).collect();
    assert!(missing.is_empty(), "missing node types: {missing:?}");
}
