//! BVH (Biovision Hierarchy) motion capture reader and reference forward kinematics.
//!
//! Grammar: `HIERARCHY`, one or more `ROOT name { ... }` blocks holding `OFFSET x y z`,
//! `CHANNELS n ...`, nested `JOINT name { ... }` and `End Site { OFFSET x y z }`, then
//! `MOTION`, `Frames: n`, `Frame Time: t` and one line of values per frame. Any mix of
//! CRLF and LF, tabs, extra spaces and blank lines is accepted. Several `ROOT`s are
//! allowed (several characters in one file); each becomes a joint without a parent.
//! Errors carry the 1-based line number and say what was expected.
//!
//! Conventions (angles in the file are degrees; lengths are the file's units):
//! - Rotation channels apply in the order listed, as intrinsic rotations: for
//!   `Zrotation Xrotation Yrotation` the local rotation is `Rz * Rx * Ry` in glam's
//!   column-vector convention (`v' = Rz * Rx * Ry * v`). This is the row-vector
//!   `v' = v * Ry * Rx * Rz` of J. Thingvold's BVH notes (University of Wisconsin
//!   CS 838, 1999, "vR = vYXZ" for ZXY channels), transposed.
//! - Translation: a joint's local translation is its `OFFSET`, except that each
//!   position channel present replaces that axis with the channel value (Blender's
//!   `import_bvh.py`: location = channel - rest offset, added back to the rest offset).
//!   Thingvold's notes instead add root position channels to the root offset; the two
//!   agree whenever the offset is zero on the channel's axis, as in both asset files.
//! - Local matrix `T(translation) * R`; world = parent world * local.

use glam::{DMat4, DQuat, DVec3};
use thiserror::Error;

/// A BVH parse error at a 1-based line number.
#[derive(Clone, Debug, Error, PartialEq)]
#[error("line {line}: {message}")]
pub struct BvhError {
    /// 1-based line number where the problem was found (the last line for a truncated file).
    pub line: usize,
    /// What was expected and what was found.
    pub message: String,
}

/// A coordinate axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// X axis.
    X,
    /// Y axis.
    Y,
    /// Z axis.
    Z,
}

impl Axis {
    fn unit(self) -> DVec3 {
        match self {
            Axis::X => DVec3::X,
            Axis::Y => DVec3::Y,
            Axis::Z => DVec3::Z,
        }
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// One motion channel of a joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    /// `Xposition`, `Yposition` or `Zposition`.
    Position(Axis),
    /// `Xrotation`, `Yrotation` or `Zrotation` (degrees).
    Rotation(Axis),
}

impl Channel {
    fn parse(s: &str) -> Option<Channel> {
        let axis = match s.as_bytes().first()?.to_ascii_uppercase() {
            b'X' => Axis::X,
            b'Y' => Axis::Y,
            b'Z' => Axis::Z,
            _ => return None,
        };
        match s.get(1..)?.to_ascii_lowercase().as_str() {
            "position" => Some(Channel::Position(axis)),
            "rotation" => Some(Channel::Rotation(axis)),
            _ => None,
        }
    }
}

/// A joint of the hierarchy. Joints are stored parent-first (file order).
#[derive(Clone, Debug, PartialEq)]
pub struct BvhJoint {
    /// Joint name (the rest of the `ROOT`/`JOINT` line, so names may contain spaces).
    pub name: String,
    /// Parent joint, `None` for a `ROOT`.
    pub parent: Option<usize>,
    /// Rest offset from the parent.
    pub offset: DVec3,
    /// Channels in file order.
    pub channels: Vec<Channel>,
    /// Offset of the `End Site` below this joint, if any.
    pub end_site: Option<DVec3>,
    /// Index of this joint's first channel within a frame's values.
    pub first_channel: usize,
}

/// A parsed BVH file.
#[derive(Clone, Debug, PartialEq)]
pub struct Bvh {
    /// Joints in file order (parents before children). End Sites are not joints.
    pub joints: Vec<BvhJoint>,
    /// Seconds per frame.
    pub frame_time: f64,
    /// Number of frames.
    pub frame_count: usize,
    /// Channel values, frame-major: frame `f` is `values[f * channel_count ..][..channel_count]`.
    pub values: Vec<f64>,
}

/// Line-tagged tokens of the hierarchy section.
struct Tokens<'a> {
    toks: Vec<(usize, &'a str)>,
    pos: usize,
    last_line: usize,
}

impl<'a> Tokens<'a> {
    fn next(&mut self, what: &str) -> Result<(usize, &'a str), BvhError> {
        let t = self.toks.get(self.pos).copied().ok_or_else(|| BvhError {
            line: self.last_line,
            message: format!("file ends where {what} was expected"),
        })?;
        self.pos += 1;
        Ok(t)
    }

    fn number(&mut self, what: &str) -> Result<f64, BvhError> {
        let (line, t) = self.next(what)?;
        parse_num(t).ok_or_else(|| BvhError {
            line,
            message: format!("expected {what} but found '{t}'"),
        })
    }

    /// The tokens remaining on `line`, stopping before a `{`.
    fn rest_of_line(&mut self, line: usize) -> Vec<&'a str> {
        let mut out = Vec::new();
        while let Some(&(l, t)) = self.toks.get(self.pos) {
            if l != line || t == "{" {
                break;
            }
            out.push(t);
            self.pos += 1;
        }
        out
    }
}

fn parse_num(t: &str) -> Option<f64> {
    t.parse::<f64>().ok().filter(|x| x.is_finite())
}

fn err<T>(line: usize, message: impl Into<String>) -> Result<T, BvhError> {
    Err(BvhError {
        line,
        message: message.into(),
    })
}

/// Parses BVH text. See the module documentation for the accepted grammar.
pub fn parse_bvh(text: &str) -> Result<Bvh, BvhError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let lines: Vec<&str> = text.split('\n').collect();
    let last_line = lines.len().max(1);
    // Find HIERARCHY and MOTION; hierarchy tokens are everything in between.
    let first = lines.iter().position(|l| !l.trim().is_empty());
    let Some(first) = first.filter(|&i| lines[i].trim().eq_ignore_ascii_case("HIERARCHY")) else {
        let line = first.map_or(1, |i| i + 1);
        return err(line, "expected HIERARCHY at the start of the file");
    };
    let motion = lines.iter().position(|l| l.split_whitespace().next() == Some("MOTION"));
    let hier_end = motion.unwrap_or(lines.len());
    let toks = lines[first + 1..hier_end]
        .iter()
        .enumerate()
        .flat_map(|(i, l)| l.split_whitespace().map(move |t| (first + 2 + i, t)))
        .collect();
    let mut tk = Tokens {
        toks,
        pos: 0,
        // Report unclosed blocks at the MOTION line (or the last line without one).
        last_line: (hier_end + 1).min(last_line),
    };
    let joints = parse_hierarchy(&mut tk)?;
    let Some(motion) = motion else {
        return err(last_line, "file ends without a MOTION section");
    };
    if lines[motion].split_whitespace().count() > 1 {
        return err(motion + 1, "unexpected text after MOTION");
    }
    let channel_count: usize = joints.iter().map(|j| j.channels.len()).sum();

    // Motion header: "Frames: n" and "Frame Time: t", each on its own line.
    let mut rest = (motion + 1..lines.len()).filter(|&i| !lines[i].trim().is_empty());
    let header = |i: Option<usize>, key: &str| -> Result<(usize, String), BvhError> {
        let Some(i) = i else {
            return err(last_line, format!("file ends where '{key}' was expected"));
        };
        let l = lines[i].trim();
        let value = l
            .get(..key.len())
            .filter(|p| p.eq_ignore_ascii_case(key))
            .map(|_| l[key.len()..].trim_start().trim_start_matches(':').trim());
        match value {
            Some(v) => Ok((i + 1, v.to_string())),
            None => err(i + 1, format!("expected '{key}: ...' but found '{l}'")),
        }
    };
    let (fl, frames) = header(rest.next(), "Frames")?;
    let frame_count: usize = frames.parse().or_else(|_| {
        err(
            fl,
            format!("expected a whole number of frames after 'Frames:' but found '{frames}'"),
        )
    })?;
    let (tl, ft) = header(rest.next(), "Frame Time")?;
    let frame_time = parse_num(&ft).filter(|&t| t > 0.0);
    let Some(frame_time) = frame_time else {
        return err(
            tl,
            format!("expected a positive number after 'Frame Time:' but found '{ft}'"),
        );
    };

    let mut values = Vec::new();
    let mut read = 0usize;
    for i in rest {
        let line = i + 1;
        if read == frame_count {
            return err(
                line,
                format!("extra data after the {frame_count} frames declared on line {fl}"),
            );
        }
        let before = values.len();
        for (k, t) in lines[i].split_whitespace().enumerate() {
            match parse_num(t) {
                Some(v) => values.push(v),
                None => {
                    return err(line, format!("frame {read}: value {} is not a number: '{t}'", k + 1));
                }
            }
        }
        let got = values.len() - before;
        if got != channel_count {
            return err(
                line,
                format!("frame {read} has {got} values but the hierarchy declares {channel_count} channels"),
            );
        }
        read += 1;
    }
    if read < frame_count && channel_count > 0 {
        return err(
            last_line,
            format!("file ends after {read} frames but 'Frames:' on line {fl} declares {frame_count}"),
        );
    }
    if channel_count == 0 {
        values.clear();
    }
    Ok(Bvh {
        joints,
        frame_time,
        frame_count,
        values,
    })
}

/// An open `{ ... }` block: a joint, or the End Site of a joint.
struct Open {
    joint: usize,
    end_site: bool,
    line: usize,
    has_offset: bool,
}

fn parse_hierarchy(tk: &mut Tokens) -> Result<Vec<BvhJoint>, BvhError> {
    let mut joints: Vec<BvhJoint> = Vec::new();
    let mut stack: Vec<Open> = Vec::new();
    let mut channel_total = 0usize;
    while tk.pos < tk.toks.len() {
        let (line, t) = tk.next("a keyword")?;
        match t {
            "ROOT" | "JOINT" => {
                if (t == "ROOT") != stack.is_empty() {
                    let m = if t == "ROOT" {
                        "ROOT inside another joint (missing '}'?)"
                    } else {
                        "JOINT outside any ROOT (use ROOT for a top-level joint)"
                    };
                    return err(line, m);
                }
                if stack.last().is_some_and(|o| o.end_site) {
                    return err(line, "End Site cannot contain joints");
                }
                let name = tk.rest_of_line(line).join(" ");
                if name.is_empty() {
                    return err(line, format!("{t} needs a name"));
                }
                expect_brace(tk, &format!("'{{' after {t} {name}"))?;
                joints.push(BvhJoint {
                    name,
                    parent: stack.last().map(|o| o.joint),
                    offset: DVec3::ZERO,
                    channels: Vec::new(),
                    end_site: None,
                    first_channel: channel_total,
                });
                stack.push(Open {
                    joint: joints.len() - 1,
                    end_site: false,
                    line,
                    has_offset: false,
                });
            }
            "End" => {
                let (l2, site) = tk.next("'Site' after 'End'")?;
                if !site.eq_ignore_ascii_case("Site") {
                    return err(l2, format!("expected 'Site' after 'End' but found '{site}'"));
                }
                tk.rest_of_line(l2);
                let Some(top) = stack.last().filter(|o| !o.end_site) else {
                    return err(line, "End Site must be inside a joint");
                };
                let joint = top.joint;
                if joints[joint].end_site.is_some() {
                    return err(line, format!("joint {} has more than one End Site", joints[joint].name));
                }
                expect_brace(tk, "'{' after End Site")?;
                stack.push(Open {
                    joint,
                    end_site: true,
                    line,
                    has_offset: false,
                });
            }
            "OFFSET" => {
                let Some(top) = stack.last_mut() else {
                    return err(line, "OFFSET outside any joint");
                };
                let x = tk.number("the OFFSET x value")?;
                let y = tk.number("the OFFSET y value")?;
                let z = tk.number("the OFFSET z value")?;
                if top.has_offset {
                    return err(line, "second OFFSET in the same block");
                }
                top.has_offset = true;
                let j = &mut joints[top.joint];
                if top.end_site {
                    j.end_site = Some(DVec3::new(x, y, z));
                } else {
                    j.offset = DVec3::new(x, y, z);
                }
            }
            "CHANNELS" => {
                let Some(top) = stack.last().filter(|o| !o.end_site) else {
                    return err(line, "CHANNELS must be inside a ROOT or JOINT block");
                };
                let joint = top.joint;
                if !joints[joint].channels.is_empty() {
                    return err(line, format!("joint {} has a second CHANNELS line", joints[joint].name));
                }
                let (l2, n) = tk.next("the channel count")?;
                let n: usize = n.parse().ok().filter(|&n| n <= 64).ok_or_else(|| BvhError {
                    line: l2,
                    message: format!("expected a channel count (0 to 64) after CHANNELS but found '{n}'"),
                })?;
                for k in 0..n {
                    let what = format!("channel {} of the {n} declared", k + 1);
                    let (l3, name) = tk.next(&what)?;
                    let c = Channel::parse(name).ok_or_else(|| BvhError {
                        line: l3,
                        message: format!(
                            "expected {what} (Xposition, Yposition, Zposition, Xrotation, \
                             Yrotation or Zrotation) but found '{name}'"
                        ),
                    })?;
                    joints[joint].channels.push(c);
                }
                channel_total += n;
                // Channels of later joints follow this joint's channels.
                joints[joint].first_channel = channel_total - n;
            }
            "}" => {
                let Some(top) = stack.pop() else {
                    return err(line, "'}' without a matching '{'");
                };
                if !top.has_offset {
                    let what = if top.end_site { "End Site" } else { "joint" };
                    return err(
                        line,
                        format!(
                            "{what} {} (opened on line {}) has no OFFSET",
                            joints[top.joint].name, top.line
                        ),
                    );
                }
            }
            other => {
                return err(
                    line,
                    format!("expected ROOT, JOINT, End Site, OFFSET, CHANNELS or '}}' but found '{other}'"),
                );
            }
        }
    }
    if let Some(top) = stack.last() {
        return err(
            tk.last_line,
            format!(
                "joint {} opened on line {} is not closed (missing '}}') before MOTION",
                joints[top.joint].name, top.line
            ),
        );
    }
    if joints.is_empty() {
        return err(tk.last_line, "the HIERARCHY has no ROOT joint");
    }
    Ok(joints)
}

fn expect_brace(tk: &mut Tokens, what: &str) -> Result<(), BvhError> {
    let (line, t) = tk.next(what)?;
    if t == "{" {
        Ok(())
    } else {
        err(line, format!("expected {what} but found '{t}'"))
    }
}

impl Bvh {
    /// Total channels per frame.
    pub fn channel_count(&self) -> usize {
        self.joints.iter().map(|j| j.channels.len()).sum()
    }

    /// The channel values of frame `frame`, or `None` when out of range.
    pub fn frame(&self, frame: usize) -> Option<&[f64]> {
        let n = self.channel_count();
        if frame >= self.frame_count {
            return None;
        }
        if n == 0 {
            return Some(&[]);
        }
        self.values.get(frame * n..(frame + 1) * n)
    }

    /// Number of End Sites (leaf markers, not joints).
    pub fn end_site_count(&self) -> usize {
        self.joints.iter().filter(|j| j.end_site.is_some()).count()
    }

    /// Index of the joint called `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// The order in which a joint's rotation channels appear, which is the order they
    /// apply as intrinsic rotations (`[Z, X, Y]` means `Rz * Rx * Ry`). `None` unless
    /// the joint has exactly three rotation channels about three different axes.
    pub fn rotation_order(&self, joint: usize) -> Option<[Axis; 3]> {
        let axes: Vec<Axis> = self
            .joints
            .get(joint)?
            .channels
            .iter()
            .filter_map(|c| match c {
                Channel::Rotation(a) => Some(*a),
                Channel::Position(_) => None,
            })
            .collect();
        match axes.as_slice() {
            &[a, b, c] if a != b && b != c && a != c => Some([a, b, c]),
            _ => None,
        }
    }

    /// Local translation and rotation of `joint` at `frame` (see the module docs for
    /// the conventions); `None` when either index is out of range.
    pub fn local_transform(&self, joint: usize, frame: usize) -> Option<(DVec3, DQuat)> {
        self.local_transform_in(joint, self.frame(frame)?)
    }

    /// [`Bvh::local_transform`] from one frame's channel values (a slice [`Bvh::frame`]
    /// gave): finding a frame costs a pass over the joints, so a loop over joints and
    /// frames takes the frames once.
    pub fn local_transform_in(&self, joint: usize, values: &[f64]) -> Option<(DVec3, DQuat)> {
        let j = self.joints.get(joint)?;
        let mut t = j.offset;
        let mut q = DQuat::IDENTITY;
        for (k, c) in j.channels.iter().enumerate() {
            let v = *values.get(j.first_channel + k)?;
            match c {
                Channel::Position(a) => t[a.index()] = v,
                Channel::Rotation(a) => q *= DQuat::from_axis_angle(a.unit(), v.to_radians()),
            }
        }
        Some((t, q))
    }

    /// World matrices of all joints at `frame` (empty when `frame` is out of range).
    pub fn world_matrices(&self, frame: usize) -> Vec<DMat4> {
        let mut out: Vec<DMat4> = Vec::with_capacity(self.joints.len());
        for (i, j) in self.joints.iter().enumerate() {
            let Some((t, q)) = self.local_transform(i, frame) else {
                return Vec::new();
            };
            let local = DMat4::from_rotation_translation(q, t);
            let parent = j.parent.and_then(|p| out.get(p)).copied().unwrap_or(DMat4::IDENTITY);
            out.push(parent * local);
        }
        out
    }

    /// World positions of all joints at `frame` by forward kinematics (empty when
    /// `frame` is out of range).
    pub fn world_positions(&self, frame: usize) -> Vec<DVec3> {
        self.world_matrices(frame).iter().map(|m| m.w_axis.truncate()).collect()
    }

    /// World positions of each joint's End Site at `frame` (`None` for joints without one).
    pub fn end_site_positions(&self, frame: usize) -> Vec<Option<DVec3>> {
        let world = self.world_matrices(frame);
        world
            .iter()
            .zip(&self.joints)
            .map(|(m, j)| j.end_site.map(|e| m.transform_point3(e)))
            .collect()
    }
}
