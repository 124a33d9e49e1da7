//! Joint maps for [`super::retarget`]: canonical humanoid names, map files and the default
//! name-based map.

use std::collections::HashSet;
use std::path::Path;
use std::sync::Arc;

use sinew_core::rig::parse::{parse, Ast};

/// Canonical humanoid joint names with aliases; `@` stands for `left`/`right`, `#` for
/// `l`/`r` (all normalized: lowercase, no separators).
const ALIASES: &[(&str, &[&str])] = &[
    ("hips", &["hips", "pelvis", "hip"]),
    ("spine", &["spine", "spine01", "lowerback"]),
    ("spine1", &["spine1", "spine02", "chest"]),
    ("spine2", &["spine2", "spine03", "upperchest"]),
    ("neck", &["neck", "neck01"]),
    ("head", &["head"]),
    (
        "@shoulder",
        &["@shoulder", "clavicle#", "#clavicle", "#shoulder", "shoulder#"],
    ),
    (
        "@arm",
        &["@arm", "@upperarm", "upperarm#", "#upperarm", "#humerus", "#arm"],
    ),
    (
        "@forearm",
        &[
            "@forearm",
            "@lowerarm",
            "lowerarm#",
            "forearm#",
            "#forearm",
            "#radius",
            "#elbow",
            "elbow#",
        ],
    ),
    ("@hand", &["@hand", "hand#", "#hand", "#wrist", "wrist#"]),
    (
        "@upleg",
        &[
            "@upleg",
            "@upperleg",
            "@thigh",
            "thigh#",
            "#thigh",
            "#femur",
            "upperleg#",
            "#upleg",
            "@hip",
            "hip#",
        ],
    ),
    (
        "@leg",
        &[
            "@leg",
            "@lowerleg",
            "@shin",
            "calf#",
            "#calf",
            "shin#",
            "#shin",
            "#tibia",
            "#knee",
            "knee#",
            "lowerleg#",
        ],
    ),
    ("@foot", &["@foot", "foot#", "#foot", "#ankle", "ankle#"]),
    (
        "@toebase",
        &["@toebase", "@toe", "ball#", "toe#", "#toe", "#toes", "#toebase"],
    ),
];

fn normalize(name: &str) -> String {
    let base = name.rsplit(':').next().unwrap_or(name);
    base.chars()
        .filter(|c| c.is_ascii_alphanumeric())
        .map(|c| c.to_ascii_lowercase())
        .collect()
}

/// The canonical humanoid name of a joint name (`"mixamorig:LeftUpLeg"` → `"leftupleg"`,
/// `"thigh_r"` → `"rightupleg"`), or `None` when it is not a known humanoid joint.
pub fn canonical(name: &str) -> Option<String> {
    let n = normalize(name);
    for (canon, aliases) in ALIASES {
        for side in [("left", "l"), ("right", "r")] {
            for a in *aliases {
                let form = a.replace('@', side.0).replace('#', side.1);
                if form == n {
                    return Some(canon.replace('@', side.0));
                }
            }
            if !canon.contains('@') {
                break;
            }
        }
    }
    None
}

/// [`canonical`] of `name` among the joint names `names` of the same skeleton: where a
/// skeleton has both a clavicle and a shoulder joint on a side (sinew's biped and the
/// `skeletonize --template humanoid` names: `clavicle_L > shoulder_L > elbow_L > wrist_L`),
/// the shoulder is the upper arm, not the clavicle that other schemes call a shoulder.
pub fn canonical_among(name: &str, names: &[String]) -> Option<String> {
    let c = canonical(name)?;
    let Some(side) = c.strip_suffix("shoulder") else {
        return Some(c);
    };
    let has_clavicle = |n: &String| normalize(n).contains("clavicle") && canonical(n).as_deref() == Some(c.as_str());
    if normalize(name).contains("shoulder") && names.iter().any(has_clavicle) {
        return Some(format!("{side}arm"));
    }
    Some(c)
}

/// Parses a map file: a RON map of source joint name to target node name.
pub fn parse_map(text: &str, path: &Path) -> Result<Vec<(String, String)>, String> {
    let file = Arc::new(path.to_path_buf());
    let root =
        parse(text, &file).map_err(|d| format!("{}:{}:{}: {}", path.display(), d.span.line, d.span.col, d.message))?;
    let Ast::Map(entries) = root.kind else {
        return Err(format!(
            "{}: write the map as {{ \"SourceJoint\": \"targetNode\", .. }}",
            path.display()
        ));
    };
    let mut out = Vec::new();
    for (k, v) in entries {
        match (k.kind, v.kind) {
            (Ast::Str { value: a, .. }, Ast::Str { value: b, .. }) => out.push((a, b)),
            _ => {
                return Err(format!(
                    "{}:{}: keys and values must be strings",
                    path.display(),
                    k.span.line
                ))
            }
        }
    }
    Ok(out)
}

/// The default map: first source and target joints whose names are equal after dropping
/// namespaces, case and separators (`mixamorig:LeftArm` = `LeftArm`), then the remaining
/// ones with the same canonical name ([`canonical_among`] their own skeleton's names).
pub fn default_map(source: &[String], target: &[String]) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut used_s = HashSet::new();
    let mut used_t = HashSet::new();
    for s in source {
        if canonical_among(s, source).is_none() {
            continue;
        }
        if let Some(t) = target
            .iter()
            .find(|t| normalize(t) == normalize(s) && !used_t.contains(*t))
        {
            used_s.insert(s.clone());
            used_t.insert(t.clone());
            out.push((s.clone(), t.clone()));
        }
    }
    for s in source.iter().filter(|s| !used_s.contains(*s)) {
        let Some(c) = canonical_among(s, source) else { continue };
        let taken = out
            .iter()
            .any(|(a, _): &(String, String)| canonical_among(a, source).as_deref() == Some(c.as_str()));
        if taken {
            continue;
        }
        if let Some(t) = target
            .iter()
            .find(|t| !used_t.contains(*t) && canonical_among(t, target).as_deref() == Some(c.as_str()))
        {
            used_t.insert(t.clone());
            out.push((s.clone(), t.clone()));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{canonical, canonical_among};

    /// Names from Mixamo, CMU/BVH, Unreal-style and the example biped (`hip_L`, `knee_L`,
    /// `ankle_L`, `ball_L`) map to the same canonical joints; `hip` alone is the pelvis.
    #[test]
    fn naming_schemes_map_to_canonical_joints() {
        let cases = [
            ("mixamorig:LeftUpLeg", "leftupleg"),
            ("thigh_r", "rightupleg"),
            ("hip_L", "leftupleg"),
            ("hip_R", "rightupleg"),
            ("hip", "hips"),
            ("Hips", "hips"),
            ("knee_L", "leftleg"),
            ("calf_l", "leftleg"),
            ("ankle_R", "rightfoot"),
            ("ball_L", "lefttoebase"),
            ("LeftToeBase", "lefttoebase"),
        ];
        for (name, want) in cases {
            assert_eq!(canonical(name).as_deref(), Some(want), "{name}");
        }
        assert_eq!(canonical("tail_03"), None);
        // The biped's arm: elbow and wrist by name, its shoulder (below a clavicle) the
        // upper arm; without a clavicle `shoulder_L` stays the clavicle.
        assert_eq!(canonical("elbow_L").as_deref(), Some("leftforearm"));
        assert_eq!(canonical("wrist_R").as_deref(), Some("righthand"));
        let biped: Vec<String> = ["clavicle_L", "shoulder_L", "elbow_L", "clavicle_R", "shoulder_R"]
            .map(String::from)
            .to_vec();
        assert_eq!(canonical_among("clavicle_L", &biped).as_deref(), Some("leftshoulder"));
        assert_eq!(canonical_among("shoulder_L", &biped).as_deref(), Some("leftarm"));
        assert_eq!(canonical_among("shoulder_R", &biped).as_deref(), Some("rightarm"));
        assert_eq!(
            canonical_among("shoulder_L", &biped[1..2]).as_deref(),
            Some("leftshoulder")
        );
    }
}
