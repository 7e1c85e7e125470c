//! The `--sweep` grammar of `fixplan study`: kit variants around a base kit.
//!
//! ```text
//! SWEEP   := CLAUSE ( ';' CLAUSE )*
//! CLAUSE  := KEY '=' ITEM ( ',' ITEM )* [ UNIT ]
//! ITEM    := NUMBER                      one value
//!          | A '..' B                    a range: 5 evenly spaced values, A and B included
//!          | A '..' B '/' N              a range of N evenly spaced values (N >= 2)
//!          | A '..' B ':' S              A, A+S, A+2S, ... up to B (S > 0)
//!          | COLS 'x' ROWS               plate only (or one number N for N x N)
//!          | MIN '..' MAX                travel only: the [min, max] pair (no ranges)
//! UNIT    := 'mm' | 'in'                 length keys only, once at the end of the clause;
//!                                        default: the catalogue's unit
//! ```
//!
//! Keys: `locator_radius`, `spacing`, `edge_trim`, `min_clearance` (lengths),
//! `plate` (holes, `COLSxROWS`), `travel` (length: `MAX` keeps the kit's
//! minimum, `MIN..MAX` sets both), `max_clamp_angle` (degrees, optional
//! `deg`), `grid_step` (integer >= 1). The points of a sweep are the
//! Cartesian product of its clauses (the first clause varies slowest).

use fixplan_catalog::KitSpec;
use fixplan_core::{validate_kit, validate_params, Units};
use std::fmt;
use thiserror::Error;

/// Values a range gives when neither `/N` nor `:S` is written.
pub const DEFAULT_RANGE_COUNT: usize = 5;
/// Most points a sweep may expand to (a typo guard).
pub const MAX_POINTS: usize = 10_000;

/// Why a sweep was refused: a study checks its sweep before any work, and
/// the message names the clause or kit to fix.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SweepError {
    /// A clause does not parse.
    #[error("sweep clause {clause:?}: {problem}")]
    Clause {
        /// The clause as written (trimmed).
        clause: String,
        /// What is wrong with it.
        problem: ClauseError,
    },
    /// Two clauses set the same key: their product would be ambiguous.
    #[error("sweep key {0:?} is given twice")]
    DuplicateKey(String),
    /// No clause at all.
    #[error("the sweep is empty (write e.g. \"locator_radius=4,6 mm; plate=18x18,24x24\")")]
    Empty,
    /// The product of the clauses has more than [`MAX_POINTS`] points.
    #[error("the sweep expands to {0} points (at most {MAX_POINTS})")]
    TooMany(usize),
    /// A point makes a kit the core refuses (SPEC section 1).
    #[error("kit {kit}: {message}")]
    Kit {
        /// The kit's name, `BASE{key=value, ...}`.
        kit: String,
        /// Why it is refused.
        message: String,
    },
}

/// What is wrong with one clause (shown after the clause by
/// [`SweepError::Clause`]).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ClauseError {
    /// No `=`.
    #[error("a clause is KEY=VALUES (e.g. locator_radius=4,6 mm)")]
    NoEquals,
    /// A key not in [`KEYS`].
    #[error("unknown key {0:?} (keys: {keys})", keys = key_names())]
    UnknownKey(String),
    /// A unit on a key that takes none, or the wrong kind of unit.
    #[error("{name} takes no unit {unit:?}", name = .key.name())]
    NoUnit {
        /// The clause's key.
        key: SweepKey,
        /// The unit written.
        unit: String,
    },
    /// Two commas in a row, or nothing after `=`.
    #[error("empty value (two commas, or nothing after =)")]
    EmptyValue,
    /// A unit (or other letters) inside a value.
    #[error("{0:?}: write the unit once at the end of the clause (e.g. 4,6,8 mm)")]
    UnitInValue(String),
    /// Not a finite number.
    #[error("{0:?} is not a number")]
    NotANumber(String),
    /// A plate size that is not a whole number >= 1.
    #[error("{what} {text:?} is not a whole number >= 1")]
    NotAWholeNumber {
        /// Which number (`plate cols`, `plate rows`, `plate size`).
        what: &'static str,
        /// The number as written.
        text: String,
    },
    /// A range without `..` before its `/` or `:`.
    #[error("{0:?}: a range is written A..B")]
    RangeSyntax(String),
    /// A range `A..B` with `A > B`.
    #[error("range {range:?} goes down ({a} > {b})")]
    RangeDown {
        /// The range as written.
        range: String,
        /// Its start.
        a: f64,
        /// Its end.
        b: f64,
    },
    /// `A..B/N` with `N < 2`.
    #[error("range {0:?}: the count after / must be >= 2")]
    RangeCount(String),
    /// A range of more than [`MAX_POINTS`] values.
    #[error("range {0:?} has more than {MAX_POINTS} values")]
    RangeTooLong(String),
    /// `A..B:S` with `S <= 0`.
    #[error("range {0:?}: the step after : must be > 0")]
    RangeStep(String),
    /// A range in a `plate` clause.
    #[error("plate takes COLSxROWS values, no ranges")]
    PlateRange,
    /// A range in a `travel` clause.
    #[error("travel takes MAX or MIN..MAX values, no ranges: list several with commas")]
    TravelRange,
    /// A travel `MIN..MAX` with `MIN > MAX`.
    #[error("travel {0:?}: MIN is above MAX")]
    TravelDown(String),
    /// A grid step that is not a whole number >= 1.
    #[error("grid_step {0} is not a whole number >= 1")]
    GridStep(f64),
}

/// What a clause sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SweepKey {
    /// `locator_radius` (length).
    LocatorRadius,
    /// `spacing`: the hole spacing (length).
    Spacing,
    /// `edge_trim` (length).
    EdgeTrim,
    /// `min_clearance` (length).
    MinClearance,
    /// `plate`: holes, `COLSxROWS`.
    Plate,
    /// `travel`: the clamp's `MAX` or `MIN..MAX` (length).
    Travel,
    /// `max_clamp_angle` (degrees).
    MaxClampAngle,
    /// `grid_step` (whole number >= 1).
    GridStep,
}

/// The keys as written in a sweep, in the order the help lists them.
pub const KEYS: &[(&str, SweepKey)] = &[
    ("locator_radius", SweepKey::LocatorRadius),
    ("spacing", SweepKey::Spacing),
    ("edge_trim", SweepKey::EdgeTrim),
    ("min_clearance", SweepKey::MinClearance),
    ("plate", SweepKey::Plate),
    ("travel", SweepKey::Travel),
    ("max_clamp_angle", SweepKey::MaxClampAngle),
    ("grid_step", SweepKey::GridStep),
];

fn key_names() -> String {
    let names: Vec<_> = KEYS.iter().map(|(n, _)| *n).collect();
    names.join(", ")
}

impl SweepKey {
    /// The key as written in a sweep (and in a point's label).
    pub fn name(self) -> &'static str {
        KEYS.iter()
            .find(|(_, k)| *k == self)
            .map_or("?", |(n, _)| n)
    }

    fn is_length(self) -> bool {
        matches!(
            self,
            SweepKey::LocatorRadius
                | SweepKey::Spacing
                | SweepKey::EdgeTrim
                | SweepKey::MinClearance
                | SweepKey::Travel
        )
    }
}

/// One value of a clause, lengths already in the catalogue's unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SweepValue {
    /// A number: a length, an angle or a grid step.
    Num(f64),
    /// A plate, `COLS x ROWS` holes.
    Plate(u32, u32),
    /// A travel `MAX`: the kit's minimum stays.
    TravelMax(f64),
    /// A travel `MIN..MAX`.
    TravelPair(f64, f64),
}

impl fmt::Display for SweepValue {
    fn fmt(&self, formatter: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SweepValue::Num(x) | SweepValue::TravelMax(x) => write!(formatter, "{}", fmt_num(*x)),
            SweepValue::Plate(c, r) => write!(formatter, "{c}x{r}"),
            SweepValue::TravelPair(a, b) => write!(formatter, "{}..{}", fmt_num(*a), fmt_num(*b)),
        }
    }
}

fn fmt_num(value: f64) -> String {
    let s = format!("{value:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

/// A parsed clause: its key and values, in order.
#[derive(Debug, Clone, PartialEq)]
pub struct Clause {
    /// What the clause sets.
    pub key: SweepKey,
    /// The values, ranges expanded, in the order written.
    pub values: Vec<SweepValue>,
}

/// A parsed sweep.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Sweep {
    /// At most one clause per key, in the order written.
    pub clauses: Vec<Clause>,
}

/// One point of a sweep: a value per clause.
pub type SweepPoint = Vec<(SweepKey, SweepValue)>;

fn round(value: f64) -> f64 {
    // Ranges accumulate rounding (0.1 + 0.2): keep 9 decimals.
    let r = (value * 1e9).round() / 1e9;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

fn parse_num(text: &str) -> Result<f64, ClauseError> {
    let t = text.trim();
    match t.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(ClauseError::NotANumber(t.to_string())),
    }
}

fn parse_int(input: &str, what: &'static str) -> Result<u32, ClauseError> {
    let t = input.trim();
    match t.parse::<u32>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(ClauseError::NotAWholeNumber {
            what,
            text: t.to_string(),
        }),
    }
}

/// Expands `A..B`, `A..B/N` or `A..B:S`.
fn expand_range(item: &str) -> Result<Vec<f64>, ClauseError> {
    let (body, spec) = match item.find(['/', ':']) {
        Some(i) => (&item[..i], Some((&item[i..i + 1], &item[i + 1..]))),
        None => (item, None),
    };
    let (a, b) = body
        .split_once("..")
        .ok_or_else(|| ClauseError::RangeSyntax(item.to_string()))?;
    let (a, b) = (parse_num(a)?, parse_num(b)?);
    if a > b {
        return Err(ClauseError::RangeDown {
            range: item.to_string(),
            a,
            b,
        });
    }
    match spec {
        None | Some(("/", _)) => {
            let n = match spec {
                Some((_, n)) => n
                    .trim()
                    .parse::<usize>()
                    .ok()
                    .filter(|&n| n >= 2)
                    .ok_or_else(|| ClauseError::RangeCount(item.to_string()))?,
                None => DEFAULT_RANGE_COUNT,
            };
            if n > MAX_POINTS {
                return Err(ClauseError::RangeTooLong(item.to_string()));
            }
            if a == b {
                return Ok(vec![a]);
            }
            Ok((0..n)
                .map(|i| round(a + (b - a) * i as f64 / (n - 1) as f64))
                .collect())
        }
        Some((_, s)) => {
            let s = parse_num(s)?;
            if s <= 0.0 {
                return Err(ClauseError::RangeStep(item.to_string()));
            }
            let n = ((b - a) / s + 1e-9).floor() as usize + 1;
            if n > MAX_POINTS {
                return Err(ClauseError::RangeTooLong(item.to_string()));
            }
            Ok((0..n).map(|i| round(a + s * i as f64)).collect())
        }
    }
}

/// Splits a trailing unit off the values (`4,6,8 mm`, `4,6,8mm`).
fn split_unit(values: &str) -> (&str, Option<&str>) {
    let v = values.trim_end();
    for u in ["mm", "in", "deg"] {
        if let Some(rest) = v.strip_suffix(u) {
            let ok = rest
                .chars()
                .last()
                .is_some_and(|c| c.is_ascii_digit() || c.is_whitespace() || c == '.');
            if ok {
                return (rest.trim_end(), Some(u));
            }
        }
    }
    (v, None)
}

/// The factor from the clause's unit to the catalogue's `units`.
fn unit_factor(unit: Option<&str>, key: SweepKey, units: Units) -> Result<f64, ClauseError> {
    match (unit, key) {
        (None, _) => Ok(1.0),
        (Some("deg"), SweepKey::MaxClampAngle) => Ok(1.0),
        (Some(u @ ("mm" | "in")), k) if k.is_length() => {
            let from = if u == "mm" { Units::Mm } else { Units::In };
            Ok(from.mm_per_unit() / units.mm_per_unit())
        }
        (Some(u), key) => Err(ClauseError::NoUnit {
            key,
            unit: u.to_string(),
        }),
    }
}

fn parse_clause(text: &str, units: Units) -> Result<Clause, ClauseError> {
    let (k, v) = text.split_once('=').ok_or(ClauseError::NoEquals)?;
    let name = k.trim();
    let key = KEYS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|&(_, k)| k)
        .ok_or_else(|| ClauseError::UnknownKey(name.to_string()))?;
    let (values, unit) = split_unit(v);
    let factor = unit_factor(unit, key, units)?;
    let mut out = Vec::new();
    for item in values.split(',') {
        let item = item.trim();
        if item.is_empty() {
            return Err(ClauseError::EmptyValue);
        }
        if item
            .chars()
            .any(|c| c.is_ascii_alphabetic() && c != 'x' && c != 'e')
        {
            return Err(ClauseError::UnitInValue(item.to_string()));
        }
        match key {
            SweepKey::Plate => out.push(parse_plate(item)?),
            SweepKey::Travel => out.push(parse_travel(item, factor)?),
            _ => out.extend(parse_numbers(key, item, factor)?),
        }
    }
    Ok(Clause { key, values: out })
}

/// `COLSxROWS`, or `N` for `N x N`.
fn parse_plate(item: &str) -> Result<SweepValue, ClauseError> {
    if item.contains("..") {
        return Err(ClauseError::PlateRange);
    }
    let (c, r) = match item.split_once('x') {
        Some((c, r)) => (parse_int(c, "plate cols")?, parse_int(r, "plate rows")?),
        None => {
            let n = parse_int(item, "plate size")?;
            (n, n)
        }
    };
    Ok(SweepValue::Plate(c, r))
}

/// `MAX` or `MIN..MAX`, times `factor`.
fn parse_travel(item: &str, factor: f64) -> Result<SweepValue, ClauseError> {
    if item.contains(['/', ':']) {
        return Err(ClauseError::TravelRange);
    }
    match item.split_once("..") {
        Some((a, b)) => {
            let (a, b) = (parse_num(a)? * factor, parse_num(b)? * factor);
            if a > b {
                return Err(ClauseError::TravelDown(item.to_string()));
            }
            Ok(SweepValue::TravelPair(round(a), round(b)))
        }
        None => Ok(SweepValue::TravelMax(round(parse_num(item)? * factor))),
    }
}

/// A number or a range, times `factor`; grid steps must come out whole.
fn parse_numbers(key: SweepKey, item: &str, factor: f64) -> Result<Vec<SweepValue>, ClauseError> {
    if item.contains('x') {
        return Err(ClauseError::NotANumber(item.to_string()));
    }
    let nums = if item.contains("..") {
        expand_range(item)?
    } else {
        vec![parse_num(item)?]
    };
    nums.into_iter()
        .map(|x| {
            let x = round(x * factor);
            if key == SweepKey::GridStep && (x.fract() != 0.0 || x < 1.0) {
                return Err(ClauseError::GridStep(x));
            }
            Ok(SweepValue::Num(x))
        })
        .collect()
}

impl Sweep {
    /// Parses a sweep; lengths are converted to `units` (the catalogue's).
    pub fn parse(text: &str, units: Units) -> Result<Sweep, SweepError> {
        let mut clauses: Vec<Clause> = Vec::new();
        for raw in text.split(';') {
            let c = raw.trim();
            if c.is_empty() {
                continue;
            }
            let clause = parse_clause(c, units).map_err(|problem| SweepError::Clause {
                clause: c.to_string(),
                problem,
            })?;
            if clauses.iter().any(|o| o.key == clause.key) {
                return Err(SweepError::DuplicateKey(clause.key.name().into()));
            }
            clauses.push(clause);
        }
        if clauses.is_empty() {
            return Err(SweepError::Empty);
        }
        let n = clauses
            .iter()
            .try_fold(1usize, |acc, c| acc.checked_mul(c.values.len()))
            .unwrap_or(usize::MAX);
        if n > MAX_POINTS {
            return Err(SweepError::TooMany(n));
        }
        Ok(Sweep { clauses })
    }

    /// Every point, first clause slowest.
    pub fn points(&self) -> Vec<SweepPoint> {
        let mut pts: Vec<SweepPoint> = vec![Vec::new()];
        for c in &self.clauses {
            pts = pts
                .into_iter()
                .flat_map(|p| {
                    c.values.iter().map(move |v| {
                        let mut q = p.clone();
                        q.push((c.key, *v));
                        q
                    })
                })
                .collect();
        }
        if self.clauses.is_empty() {
            Vec::new()
        } else {
            pts
        }
    }
}

/// `key=value, key=value` of a point (lengths in the catalogue's unit).
pub fn point_label(point: &[(SweepKey, SweepValue)]) -> String {
    point
        .iter()
        .map(|(k, v)| format!("{}={v}", k.name()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The base kit with a point applied, checked (SPEC section 1). Its name is
/// `BASE{key=value, ...}`.
pub fn apply(base: &KitSpec, point: &[(SweepKey, SweepValue)]) -> Result<KitSpec, SweepError> {
    let mut k = base.clone();
    k.name = format!("{}{{{}}}", base.name, point_label(point));
    for &(key, v) in point {
        match (key, v) {
            (SweepKey::LocatorRadius, SweepValue::Num(x)) => k.kit.locator_radius = x,
            (SweepKey::Spacing, SweepValue::Num(x)) => k.kit.spacing = x,
            (SweepKey::EdgeTrim, SweepValue::Num(x)) => k.params.edge_trim = Some(x),
            (SweepKey::MinClearance, SweepValue::Num(x)) => k.params.min_clearance = Some(x),
            (SweepKey::MaxClampAngle, SweepValue::Num(x)) => k.params.max_clamp_angle_deg = x,
            (SweepKey::GridStep, SweepValue::Num(x)) => k.params.grid_step = x as u32,
            (SweepKey::Plate, SweepValue::Plate(c, r)) => {
                k.kit.cols = c;
                k.kit.rows = r;
            }
            (SweepKey::Travel, SweepValue::TravelMax(t)) => k.kit.clamp.travel[1] = t,
            (SweepKey::Travel, SweepValue::TravelPair(a, b)) => k.kit.clamp.travel = [a, b],
            (key, v) => {
                return Err(SweepError::Kit {
                    kit: k.name.clone(),
                    message: format!("{} cannot take {v}", key.name()),
                })
            }
        }
    }
    let units = Units::Mm; // validate_params only reads defaults
    validate_kit(&k.kit)
        .and_then(|_| validate_params(&k.params, units))
        .map_err(|e| SweepError::Kit {
            kit: k.name.clone(),
            message: e.to_string(),
        })?;
    Ok(k)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nums(sweep: &Sweep, index: usize) -> Vec<f64> {
        sweep.clauses[index]
            .values
            .iter()
            .map(|v| match v {
                SweepValue::Num(x) | SweepValue::TravelMax(x) => *x,
                _ => f64::NAN,
            })
            .collect()
    }

    #[test]
    fn lists_ranges_units() {
        let s = Sweep::parse(
            "locator_radius=4,6,8 mm; plate=18x18,24x24; travel=30..70 mm",
            Units::Mm,
        )
        .unwrap();
        assert_eq!(nums(&s, 0), vec![4.0, 6.0, 8.0]);
        assert_eq!(
            s.clauses[1].values,
            vec![SweepValue::Plate(18, 18), SweepValue::Plate(24, 24)]
        );
        assert_eq!(
            s.clauses[2].values,
            vec![SweepValue::TravelPair(30.0, 70.0)]
        );
        assert_eq!(s.points().len(), 6);
        assert_eq!(
            point_label(&s.points()[1]),
            "locator_radius=4, plate=24x24, travel=30..70"
        );
        let s = Sweep::parse("spacing=20..30", Units::Mm).unwrap();
        assert_eq!(nums(&s, 0), vec![20.0, 22.5, 25.0, 27.5, 30.0]);
        let s = Sweep::parse("spacing=20..30/3", Units::Mm).unwrap();
        assert_eq!(nums(&s, 0), vec![20.0, 25.0, 30.0]);
        let s = Sweep::parse("max_clamp_angle=30..90:20 deg", Units::Mm).unwrap();
        assert_eq!(nums(&s, 0), vec![30.0, 50.0, 70.0, 90.0]);
        let s = Sweep::parse("edge_trim=0.1..0.3:0.1", Units::Mm).unwrap();
        assert_eq!(nums(&s, 0), vec![0.1, 0.2, 0.3]);
        // Unit conversion both ways, suffix glued or not.
        let s = Sweep::parse("locator_radius=0.25in", Units::Mm).unwrap();
        assert_eq!(nums(&s, 0), vec![6.35]);
        let s = Sweep::parse("locator_radius=6.35 mm; travel=2", Units::In).unwrap();
        assert_eq!(nums(&s, 0), vec![0.25]);
        assert_eq!(s.clauses[1].values, vec![SweepValue::TravelMax(2.0)]);
        let s = Sweep::parse("plate=20; grid_step=1..3:1;", Units::Mm).unwrap();
        assert_eq!(s.clauses[0].values, vec![SweepValue::Plate(20, 20)]);
        assert_eq!(nums(&s, 1), vec![1.0, 2.0, 3.0]);
        assert_eq!(s.points().len(), 3);
    }

    #[test]
    fn errors_name_the_problem() {
        let err = |s: &str| Sweep::parse(s, Units::Mm).unwrap_err().to_string();
        assert!(
            err("radius=4").contains("unknown key \"radius\""),
            "{}",
            err("radius=4")
        );
        assert!(err("locator_radius").contains("KEY=VALUES"));
        assert!(err("locator_radius=4,,6").contains("empty value"));
        assert!(err("locator_radius=").contains("empty value"));
        assert!(err("locator_radius=four").contains("unit once"));
        assert!(err("locator_radius=4mm,6mm").contains("unit once"));
        assert!(err("plate=18x18 mm").contains("takes no unit"));
        assert!(err("grid_step=1.5").contains("whole number"));
        assert!(err("grid_step=0").contains("whole number"));
        assert!(err("plate=18x0").contains("plate rows"));
        assert!(err("plate=10..20").contains("no ranges"));
        assert!(err("travel=30..70/3").contains("no ranges"));
        assert!(err("travel=70..30").contains("MIN is above MAX"));
        assert!(err("spacing=30..20").contains("goes down"));
        assert!(err("spacing=20..30/1").contains(">= 2"));
        assert!(err("spacing=20..30:0").contains("> 0"));
        assert!(err("spacing=1;spacing=2").contains("twice"));
        assert!(err(" ; ").contains("empty"));
        assert!(err("spacing=1..100000:1").contains("more than"));
        assert!(
            err("spacing=1..100:1; locator_radius=1..200:1").contains("expands to 20000"),
            "{}",
            err("spacing=1..100:1; locator_radius=1..200:1")
        );
        assert!(err("spacing=1e999").contains("not a number"));
    }

    #[test]
    fn apply_checks_the_kit() {
        let base = fixplan_catalog::load_kit("metric-25", Units::Mm).unwrap();
        let s = Sweep::parse("travel=30; plate=10x12", Units::Mm).unwrap();
        let e = apply(&base, &s.points()[0]).unwrap_err().to_string();
        assert!(e.contains("metric-25{travel=30, plate=10x12}"), "{e}");
        assert!(e.contains("travel min 60 is above max 30"), "{e}");
        let s = Sweep::parse("travel=40..70; plate=10x12; locator_radius=5", Units::Mm).unwrap();
        let k = apply(&base, &s.points()[0]).unwrap();
        assert_eq!(k.kit.clamp.travel, [40.0, 70.0]);
        assert_eq!((k.kit.cols, k.kit.rows), (10, 12));
        assert_eq!(k.kit.locator_radius, 5.0);
        let s = Sweep::parse("locator_radius=13", Units::Mm).unwrap();
        let e = apply(&base, &s.points()[0]).unwrap_err().to_string();
        assert!(e.contains("too large"), "{e}");
    }
}
