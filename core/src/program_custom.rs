//! Custom attribute declarations in a compiled program's bytes: each node lists its
//! custom attributes after its type, and loading rebuilds its [`crate::CustomNode`] from
//! the registered type, so handles to custom attributes resolve in a loaded program too.
//!
//! Per attribute: name, short name, type, direction, default, flags (keyable, multi),
//! children and their short names, enum names, unit, doc, mirror role and the four
//! limits. Reading validates like [`AttrSpec::validate_custom`] (through the node type).

use crate::error::Result;
use crate::program_codec::{Reader, Writer};
use crate::spec::{AttrSpec, Direction, MirrorRole, Unit};
use crate::value::{AttrType, Value};

const UNITS: [Unit; 4] = [Unit::None, Unit::Degrees, Unit::Distance, Unit::Frames];
const MIRRORS: [MirrorRole; 8] = [
    MirrorRole::None,
    MirrorRole::Translate,
    MirrorRole::Rotate,
    MirrorRole::JointOrient,
    MirrorRole::RotateOrder,
    MirrorRole::WorldVector,
    MirrorRole::LocalVector,
    MirrorRole::Matrix,
];

fn index_of<T: PartialEq>(all: &[T], x: &T) -> u8 {
    all.iter().position(|y| y == x).unwrap_or(0) as u8
}

impl Writer {
    fn opt_str(&mut self, s: Option<&str>) {
        match s {
            None => self.u8(0),
            Some(s) => {
                self.u8(1);
                self.str(s);
            }
        }
    }

    fn opt_names(&mut self, n: &Option<[String; 3]>) {
        match n {
            None => self.u8(0),
            Some(n) => {
                self.u8(1);
                n.iter().for_each(|s| self.str(s));
            }
        }
    }

    fn opt_f64(&mut self, x: Option<f64>) {
        match x {
            None => self.u8(0),
            Some(x) => {
                self.u8(1);
                self.f64(x);
            }
        }
    }

    /// Writes a node's custom attribute declarations.
    pub(crate) fn custom_attrs(&mut self, attrs: &[AttrSpec]) {
        self.varint(attrs.len() as u64);
        for a in attrs {
            self.str(&a.name);
            self.opt_str(a.short_name.as_deref());
            self.u8(index_of(&AttrType::ALL, &a.ty));
            self.u8((a.direction == Direction::Output) as u8);
            if a.default.attr_type().is_heavy() {
                self.u8(1);
                self.shared(&a.default);
            } else {
                self.u8(0);
                self.small(&a.default);
            }
            self.u8(a.keyable as u8 | (a.multi as u8) << 1);
            self.opt_names(&a.children);
            self.opt_names(&a.child_short_names);
            self.varint(a.enum_names.len() as u64);
            a.enum_names.iter().for_each(|n| self.str(n));
            self.u8(index_of(&UNITS, &a.unit));
            self.str(&a.doc);
            self.u8(index_of(&MIRRORS, &a.mirror));
            for x in [a.min, a.max, a.soft_min, a.soft_max] {
                self.opt_f64(x);
            }
        }
    }
}

impl Reader<'_> {
    fn opt_string(&mut self, what: &str) -> Result<Option<String>> {
        Ok(match self.u8(what)? {
            0 => None,
            1 => Some(self.str(what)?.to_string()),
            t => return Err(self.fail(&format!("{what}: bad flag {t}"))),
        })
    }

    fn opt_names(&mut self, what: &str) -> Result<Option<[String; 3]>> {
        Ok(match self.u8(what)? {
            0 => None,
            1 => Some([
                self.str(what)?.to_string(),
                self.str(what)?.to_string(),
                self.str(what)?.to_string(),
            ]),
            t => return Err(self.fail(&format!("{what}: bad flag {t}"))),
        })
    }

    fn opt_f64(&mut self, what: &str) -> Result<Option<f64>> {
        Ok(match self.u8(what)? {
            0 => None,
            1 => Some(self.f64(what)?),
            t => return Err(self.fail(&format!("{what}: bad flag {t}"))),
        })
    }

    fn pick<T: Copy>(&mut self, all: &[T], what: &str) -> Result<T> {
        let i = self.u8(what)? as usize;
        all.get(i)
            .copied()
            .ok_or_else(|| self.fail(&format!("{what} {i} out of range")))
    }

    /// Reads a node's custom attribute declarations.
    pub(crate) fn custom_attrs(&mut self) -> Result<Vec<AttrSpec>> {
        let n = self.count(12, "custom attributes")?;
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            let name = self.str("custom attribute name")?.to_string();
            let short_name = self.opt_string("short name")?;
            let ty = self.pick(&AttrType::ALL, "attribute type")?;
            let direction = match self.u8("direction")? {
                0 => Direction::Input,
                1 => Direction::Output,
                t => return Err(self.fail(&format!("bad direction {t}"))),
            };
            let default: Value = match self.u8("default tag")? {
                0 => self.value(&[])?,
                1 => self.shared()?,
                t => return Err(self.fail(&format!("bad default tag {t}"))),
            };
            let flags = self.u8("attribute flags")?;
            let children = self.opt_names("children")?;
            let child_short_names = self.opt_names("child short names")?;
            let k = self.count(1, "enum names")?;
            let enum_names = (0..k)
                .map(|_| self.str("enum name").map(str::to_string))
                .collect::<Result<Vec<_>>>()?;
            let unit = self.pick(&UNITS, "unit")?;
            let doc = self.str("doc")?.to_string();
            let mirror = self.pick(&MIRRORS, "mirror role")?;
            let [min, max, soft_min, soft_max] = [
                self.opt_f64("min")?,
                self.opt_f64("max")?,
                self.opt_f64("soft min")?,
                self.opt_f64("soft max")?,
            ];
            out.push(AttrSpec {
                name,
                ty,
                direction,
                default,
                keyable: flags & 1 != 0,
                multi: flags & 2 != 0,
                children,
                enum_names,
                unit,
                doc,
                mirror,
                short_name,
                child_short_names,
                min,
                max,
                soft_min,
                soft_max,
            });
        }
        Ok(out)
    }
}
