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
        ],
    ),
    ("@hand", &["@hand", "hand#", "#hand", "#wrist"]),
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

/// Parses a map file: a RON map of source joint name to target node name.
pub fn parse_map(text: &str, path: &Path) -> Result<Vec<(String, String)>, String> {
    let file: Arc<Path> = Arc::from(path);
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
/// ones with the same [`canonical`] name.
pub fn default_map(source: &[String], target: &[String]) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut used_s = HashSet::new();
    let mut used_t = HashSet::new();
    for s in source {
        if canonical(s).is_none() {
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
        let Some(c) = canonical(s) else { continue };
        let taken = out
            .iter()
            .any(|(a, _): &(String, String)| canonical(a).as_deref() == Some(c.as_str()));
        if taken {
            continue;
        }
        if let Some(t) = target
            .iter()
            .find(|t| !used_t.contains(*t) && canonical(t).as_deref() == Some(c.as_str()))
        {
            used_t.insert(t.clone());
            out.push((s.clone(), t.clone()));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::canonical;

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
    }
}
