//! Length units of source files. A catalogue is in mm or in (SPEC's
//! [`Units`]); the files feeding it may be in other units that CAD tools
//! commonly write, and are converted on reading.

use fixplan_core::Units;

/// A unit a part file may be drawn in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LengthUnit {
    /// Millimetres.
    Mm,
    /// Centimetres.
    Cm,
    /// Metres.
    M,
    /// Inches.
    In,
    /// Feet.
    Ft,
}

impl LengthUnit {
    /// Millimetres per unit: conversions go through mm, so each unit needs
    /// one number.
    pub fn mm(self) -> f64 {
        match self {
            LengthUnit::Mm => 1.0,
            LengthUnit::Cm => 10.0,
            LengthUnit::M => 1000.0,
            LengthUnit::In => 25.4,
            LengthUnit::Ft => 304.8,
        }
    }

    /// The short name messages use after numbers.
    pub fn label(self) -> &'static str {
        match self {
            LengthUnit::Mm => "mm",
            LengthUnit::Cm => "cm",
            LengthUnit::M => "m",
            LengthUnit::In => "in",
            LengthUnit::Ft => "ft",
        }
    }

    /// Factor that converts a length in `self` to `to`: what readers
    /// multiply file coordinates by.
    pub fn factor_to(self, to: Units) -> f64 {
        self.mm() / to.mm_per_unit()
    }

    /// Accepts the usual spellings; anything else is an error the caller
    /// reports as "unknown units".
    pub fn parse(text: &str) -> Option<LengthUnit> {
        Some(match text.trim().to_ascii_lowercase().as_str() {
            "mm" | "millimeter" | "millimeters" | "millimetre" | "millimetres" => LengthUnit::Mm,
            "cm" | "centimeter" | "centimeters" | "centimetre" | "centimetres" => LengthUnit::Cm,
            "m" | "meter" | "meters" | "metre" | "metres" => LengthUnit::M,
            "in" | "inch" | "inches" => LengthUnit::In,
            "ft" | "foot" | "feet" => LengthUnit::Ft,
            _ => return None,
        })
    }
}

impl From<Units> for LengthUnit {
    fn from(units: Units) -> Self {
        match units {
            Units::Mm => LengthUnit::Mm,
            Units::In => LengthUnit::In,
        }
    }
}

/// A catalogue or kit `units` other than the two SPEC knows (the text as
/// written).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown units \"{0}\": a catalogue or kit is in \"mm\" or \"in\"")]
pub struct UnknownUnits(pub String);

/// A catalogue or kit unit: only the two SPEC knows, because the solver
/// works in those.
pub fn parse_units(text: &str) -> Result<Units, UnknownUnits> {
    match LengthUnit::parse(text) {
        Some(LengthUnit::Mm) => Ok(Units::Mm),
        Some(LengthUnit::In) => Ok(Units::In),
        _ => Err(UnknownUnits(text.to_string())),
    }
}
