//! Units: what `currentUnit` says, and the rules that turn Maya's numbers into sinew's.
//!
//! Maya stores three kinds of numbers in a `.ma` file (Maya documentation, *currentUnit*
//! and *unitConversion*):
//! - attribute values of linear, angular and time attributes are written in the **UI
//!   units** of `currentUnit -l … -a … -t …` (defaults centimeter, degree, film);
//! - typed data (matrices, `xform` matrices, geometry points and deltas) is written in the
//!   **internal units**: centimetres and radians;
//! - a `unitConversion` node's `conversionFactor` converts the source plug's *internal*
//!   value into the destination's internal value (radians → a plain number that reads as
//!   degrees is `57.2957…`).
//!
//! sinew's conventions: angles on plugs are degrees (whatever the file's angle unit),
//! lengths stay in the file's linear unit (times `--scale`), times are frames of the file's
//! time unit (the rig's `fps` is that unit's rate). [`Units::to_sinew`] gives, per unit
//! class, the factor *sinew value per Maya internal value*; a value written in UI units is
//! first taken to internal units ([`Units::ui_to_internal`]). A conversion factor becomes
//! `cf · k(dst) / k(src)` in sinew, which is exactly 1 for the usual degree ↔ number
//! conversions (the node is then dropped and the plugs connected directly).

/// The unit class of an attribute: how its values convert.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnitClass {
    /// A plain number (also booleans, enums, integers).
    None,
    /// A length.
    Linear,
    /// An angle.
    Angle,
    /// A time.
    Time,
}

/// Maya's time unit resolution: internal time is counted in 6000ths of a second (the
/// `MTime` tick of the unit-conversion nodes).
pub const TICKS_PER_SECOND: f64 = 6000.0;

/// The file's units.
#[derive(Clone, Debug, PartialEq)]
pub struct Units {
    /// Linear unit name as written.
    pub linear: String,
    /// Centimetres per linear unit.
    pub cm_per_unit: f64,
    /// Angular unit name as written.
    pub angle: String,
    /// Radians per angular unit.
    pub rad_per_unit: f64,
    /// Time unit name as written.
    pub time: String,
    /// Frames per second of the time unit.
    pub fps: f64,
    /// Extra scale applied to every length (`--scale`), 1 by default.
    pub scale: f64,
}

impl Default for Units {
    fn default() -> Self {
        Units {
            linear: "centimeter".into(),
            cm_per_unit: 1.0,
            angle: "degree".into(),
            rad_per_unit: std::f64::consts::PI / 180.0,
            time: "film".into(),
            fps: 24.0,
            scale: 1.0,
        }
    }
}

/// Centimetres per linear unit, by Maya's long or short name.
pub fn linear_unit(name: &str) -> Option<f64> {
    Some(match name {
        "mm" | "millimeter" => 0.1,
        "cm" | "centimeter" => 1.0,
        "m" | "meter" => 100.0,
        "km" | "kilometer" => 100_000.0,
        "in" | "inch" => 2.54,
        "ft" | "foot" => 30.48,
        "yd" | "yard" => 91.44,
        "mi" | "mile" => 160_934.4,
        _ => return None,
    })
}

/// Radians per angular unit, by Maya's long or short name.
pub fn angle_unit(name: &str) -> Option<f64> {
    let deg = std::f64::consts::PI / 180.0;
    Some(match name {
        "deg" | "degree" => deg,
        "rad" | "radian" => 1.0,
        "min" | "minute" => deg / 60.0,
        "sec" | "second" => deg / 3600.0,
        _ => return None,
    })
}

/// Frames per second of a time unit: Maya's names (`game` 15, `film` 24, `pal` 25, `ntsc`
/// 30, `show` 48, `palf` 50, `ntscf` 60, `hour`, `min`, `sec`, `millisec`) and the
/// `<rate>fps` / `<rate>df` forms (`23.976fps`, `29.97df`).
pub fn time_unit(name: &str) -> Option<f64> {
    let fixed = match name {
        "game" => 15.0,
        "film" => 24.0,
        "pal" => 25.0,
        "ntsc" => 30.0,
        "show" => 48.0,
        "palf" => 50.0,
        "ntscf" => 60.0,
        "hour" => 1.0 / 3600.0,
        "min" => 1.0 / 60.0,
        "sec" => 1.0,
        "millisec" => 1000.0,
        _ => 0.0,
    };
    if fixed > 0.0 {
        return Some(fixed);
    }
    let rate = name.strip_suffix("fps").or_else(|| name.strip_suffix("df"))?;
    rate.parse::<f64>().ok().filter(|r| r.is_finite() && *r > 0.0)
}

impl Units {
    /// Sinew value per Maya internal value, for a unit class (see the module docs).
    pub fn to_sinew(&self, class: UnitClass) -> f64 {
        match class {
            UnitClass::None => 1.0,
            UnitClass::Linear => self.scale / self.cm_per_unit,
            UnitClass::Angle => 180.0 / std::f64::consts::PI,
            UnitClass::Time => self.fps / TICKS_PER_SECOND,
        }
    }

    /// Maya internal value per UI value (what `currentUnit` means for attribute values).
    pub fn ui_to_internal(&self, class: UnitClass) -> f64 {
        match class {
            UnitClass::None => 1.0,
            UnitClass::Linear => self.cm_per_unit,
            UnitClass::Angle => self.rad_per_unit,
            UnitClass::Time => TICKS_PER_SECOND / self.fps,
        }
    }

    /// Converts a value written in UI units to sinew. Exact (no arithmetic at all) when the
    /// UI unit is sinew's: degrees, frames, and lengths with no `--scale`.
    pub fn ui_value(&self, class: UnitClass, v: f64) -> f64 {
        match class {
            UnitClass::None | UnitClass::Time => v,
            UnitClass::Linear if self.scale == 1.0 => v,
            UnitClass::Linear => v * self.scale,
            UnitClass::Angle if self.angle == "deg" || self.angle == "degree" => v,
            UnitClass::Angle => (v * self.rad_per_unit).to_degrees(),
        }
    }

    /// Converts a length written in internal units (centimetres, as in matrices and
    /// geometry) to sinew. Exact for centimetre files without `--scale`.
    pub fn internal_length(&self, v: f64) -> f64 {
        if self.cm_per_unit == 1.0 && self.scale == 1.0 {
            v
        } else {
            v * self.to_sinew(UnitClass::Linear)
        }
    }

    /// The sinew factor of a Maya conversion factor `cf` from a plug of class `src` to one
    /// of class `dst`: `cf · k(dst) / k(src)`, snapped to exactly 1 within 1e-12 (the usual
    /// degree ↔ radian pairs, which cancel up to rounding).
    pub fn conversion(&self, cf: f64, src: UnitClass, dst: UnitClass) -> f64 {
        let f = cf * self.to_sinew(dst) / self.to_sinew(src);
        if (f - 1.0).abs() <= 1e-12 {
            1.0
        } else {
            f
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_tables() {
        assert_eq!(linear_unit("m"), Some(100.0));
        assert_eq!(angle_unit("rad"), Some(1.0));
        assert_eq!(time_unit("ntsc"), Some(30.0));
        assert_eq!(time_unit("23.976fps"), Some(23.976));
        assert_eq!(time_unit("29.97df"), Some(29.97));
        assert_eq!(time_unit("0fps"), None);
        assert_eq!(time_unit("bogus"), None);
    }

    #[test]
    fn degree_conversions_cancel_to_one() {
        let u = Units::default();
        // Maya's radian-to-number factor on an angle source: the number reads as degrees.
        assert_eq!(
            u.conversion(57.295_779_513_082_32, UnitClass::Angle, UnitClass::None),
            1.0
        );
        assert_eq!(
            u.conversion(0.017453292519943295, UnitClass::None, UnitClass::Angle),
            1.0
        );
        // A factor that means something else stays.
        assert!((u.conversion(2.0, UnitClass::None, UnitClass::None) - 2.0).abs() < 1e-15);
    }

    #[test]
    fn lengths_and_angles_from_ui_units() {
        let u = Units {
            linear: "meter".into(),
            cm_per_unit: 100.0,
            angle: "radian".into(),
            rad_per_unit: 1.0,
            scale: 0.5,
            ..Units::default()
        };
        assert_eq!(u.ui_value(UnitClass::Linear, 4.0), 2.0);
        assert!((u.ui_value(UnitClass::Angle, std::f64::consts::PI) - 180.0).abs() < 1e-12);
        // 300 cm in a metre file, halved: 1.5.
        assert!((u.internal_length(300.0) - 1.5).abs() < 1e-12);
        // A metre-file conversion from a length (internal cm) to a number that shows metres:
        // Maya's factor is 0.01; in sinew the length is already in metres (times 0.5).
        assert!((u.conversion(0.01, UnitClass::Linear, UnitClass::None) - 2.0).abs() < 1e-12);
    }
}
