//! Units: what the catalog's numeric columns measure and what a literal such as `50 km/h` means.
//!
//! A column's [`Unit`] is data of the catalog; the checker reads every number against it. A
//! [`Measure`] is the working form both share: the powers of length, time and angle, the size
//! of one unit in the base units (metre, second, degree: the catalog's own, so a converted
//! literal needs no scaling for any column but time), and whether it is an instant (a point in
//! time, which only a duration may be added to).

use std::fmt;

/// Powers of the three base dimensions: length (m), time (s) and angle (deg).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Dims {
    /// Power of length.
    pub length: i8,
    /// Power of time.
    pub time: i8,
    /// Power of angle.
    pub angle: i8,
}

impl Dims {
    /// No dimension: a count, a ratio, a bare number.
    pub const NONE: Dims = Dims::new(0, 0, 0);
    /// A length.
    pub const LENGTH: Dims = Dims::new(1, 0, 0);
    /// A time (an instant or a duration).
    pub const TIME: Dims = Dims::new(0, 1, 0);
    /// A speed.
    pub const SPEED: Dims = Dims::new(1, -1, 0);
    /// An acceleration.
    pub const ACCEL: Dims = Dims::new(1, -2, 0);
    /// An angle.
    pub const ANGLE: Dims = Dims::new(0, 0, 1);
    /// An angular rate.
    pub const ANGULAR_RATE: Dims = Dims::new(0, -1, 1);

    /// Dimensions with these powers.
    pub const fn new(length: i8, time: i8, angle: i8) -> Dims {
        Dims {
            length,
            time,
            angle,
        }
    }

    /// The dimensions of a product.
    pub fn times(self, o: Dims) -> Dims {
        Dims::new(
            self.length.saturating_add(o.length),
            self.time.saturating_add(o.time),
            self.angle.saturating_add(o.angle),
        )
    }

    /// The dimensions of a quotient.
    pub fn over(self, o: Dims) -> Dims {
        Dims::new(
            self.length.saturating_sub(o.length),
            self.time.saturating_sub(o.time),
            self.angle.saturating_sub(o.angle),
        )
    }

    /// What these dimensions measure, in words ("a speed"), for messages.
    pub fn describe(self) -> String {
        match self {
            Dims::NONE => "a plain number".into(),
            Dims::LENGTH => "a distance".into(),
            Dims::TIME => "a time".into(),
            Dims::SPEED => "a speed".into(),
            Dims::ACCEL => "an acceleration".into(),
            Dims::ANGLE => "an angle".into(),
            Dims::ANGULAR_RATE => "an angular rate".into(),
            d => format!("a quantity in {}", base_symbol(d)),
        }
    }
}

/// The dimensions written in base units, e.g. `m/s2`, `m*deg`.
fn base_symbol(d: Dims) -> String {
    let mut num = Vec::new();
    let mut den = Vec::new();
    for (sym, p) in [("m", d.length), ("s", d.time), ("deg", d.angle)] {
        let part = |p: i8| {
            if p == 1 {
                sym.to_string()
            } else {
                format!("{sym}{p}")
            }
        };
        match p.cmp(&0) {
            std::cmp::Ordering::Greater => num.push(part(p)),
            std::cmp::Ordering::Less => den.push(part(-p)),
            std::cmp::Ordering::Equal => {}
        }
    }
    let num = if num.is_empty() {
        "1".to_string()
    } else {
        num.join("*")
    };
    if den.is_empty() {
        num
    } else {
        format!("{num}/{}", den.join("/"))
    }
}

/// What a number measures and in what size of unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measure {
    /// The dimensions.
    pub dims: Dims,
    /// One unit in base units (m, s, deg): 1 for the catalog's columns, 0.1 for a frame.
    pub factor: f64,
    /// Whether it is a point in time (a frame, a timestamp), not a duration.
    pub instant: bool,
}

impl Measure {
    /// A plain number.
    pub const NONE: Measure = Measure::base(Dims::NONE);

    /// A measure in base units (factor 1), not an instant.
    pub const fn base(dims: Dims) -> Measure {
        Measure {
            dims,
            factor: 1.0,
            instant: false,
        }
    }

    /// The duration between two instants of this measure (or the measure itself).
    pub fn as_duration(self) -> Measure {
        Measure {
            instant: false,
            ..self
        }
    }

    /// The measure in words with its unit, e.g. "a speed (m/s)", "a time (frames of 0.1 s)".
    pub fn describe(self) -> String {
        let what = if self.instant {
            "an instant".to_string()
        } else if self.dims == Dims::TIME {
            "a duration".to_string()
        } else {
            self.dims.describe()
        };
        if self.dims == Dims::NONE {
            return what;
        }
        format!("{what} ({})", self.symbol())
    }

    /// The unit written as a literal's unit: `m/s`, `deg`, `s`; a frame is "frames of 0.1 s".
    pub fn symbol(self) -> String {
        if self.dims == Dims::TIME && (self.factor - FRAME_S).abs() < 1e-12 {
            return "frames of 0.1 s".into();
        }
        if self.dims == Dims::TIME && (self.factor - 1e-9).abs() < 1e-21 {
            return "ns".into();
        }
        let base = base_symbol(self.dims);
        if (self.factor - 1.0).abs() < 1e-12 {
            base
        } else {
            format!("{} {base}", self.factor)
        }
    }
}

/// A frame's length in seconds: the time columns count frames of a 0.1 s grid.
pub const FRAME_S: f64 = 0.1;

/// The unit of a catalog column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Unit {
    /// Not a number, or a number that is a name (an id): no unit.
    None,
    /// A count or a rank: a plain number.
    Count,
    /// Metres.
    Metre,
    /// Metres per second.
    MetrePerSecond,
    /// Metres per second squared.
    MetrePerSecond2,
    /// Degrees.
    Degree,
    /// Degrees per second.
    DegreePerSecond,
    /// An instant as a frame of the 0.1 s grid (every `time` column).
    Frame,
    /// An instant in seconds from the log's start.
    SecondsFromStart,
    /// An instant in nanoseconds (a timestamp).
    Nanoseconds,
}

impl Unit {
    /// The unit as the catalog writes it after the column's type (`m/s`, `deg`); empty for
    /// [`Unit::None`] and [`Unit::Count`].
    pub fn symbol(self) -> &'static str {
        match self {
            Unit::None | Unit::Count => "",
            Unit::Metre => "m",
            Unit::MetrePerSecond => "m/s",
            Unit::MetrePerSecond2 => "m/s2",
            Unit::Degree => "deg",
            Unit::DegreePerSecond => "deg/s",
            Unit::Frame => "frame",
            Unit::SecondsFromStart => "s",
            Unit::Nanoseconds => "ns",
        }
    }

    /// What a number of this unit measures; `None` for a column that is not a quantity.
    pub fn measure(self) -> Option<Measure> {
        let instant = |factor| Measure {
            dims: Dims::TIME,
            factor,
            instant: true,
        };
        Some(match self {
            Unit::None => return None,
            Unit::Count => Measure::NONE,
            Unit::Metre => Measure::base(Dims::LENGTH),
            Unit::MetrePerSecond => Measure::base(Dims::SPEED),
            Unit::MetrePerSecond2 => Measure::base(Dims::ACCEL),
            Unit::Degree => Measure::base(Dims::ANGLE),
            Unit::DegreePerSecond => Measure::base(Dims::ANGULAR_RATE),
            Unit::Frame => instant(FRAME_S),
            Unit::SecondsFromStart => instant(1.0),
            Unit::Nanoseconds => instant(1e-9),
        })
    }
}

impl fmt::Display for Unit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

/// One unit a literal may carry: its name as written, its dimensions and its size in base
/// units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiteralUnit {
    /// The name as written (`km`, `h`, `rad`).
    pub name: &'static str,
    /// Its dimensions.
    pub dims: Dims,
    /// One of it in base units.
    pub factor: f64,
}

const fn lit(name: &'static str, dims: Dims, factor: f64) -> LiteralUnit {
    LiteralUnit { name, dims, factor }
}

/// Degrees in a radian.
const DEG_PER_RAD: f64 = 180.0 / std::f64::consts::PI;

/// The units a literal may be written in. A literal's unit is one of these, or a quotient of
/// two (`km/h`, `rad/s`, `m/s2` — a trailing `2` squares a unit).
pub const LITERAL_UNITS: &[LiteralUnit] = &[
    lit("m", Dims::LENGTH, 1.0),
    lit("km", Dims::LENGTH, 1000.0),
    lit("cm", Dims::LENGTH, 0.01),
    lit("mm", Dims::LENGTH, 0.001),
    lit("ft", Dims::LENGTH, 0.3048),
    lit("mi", Dims::LENGTH, 1609.344),
    lit("s", Dims::TIME, 1.0),
    lit("ms", Dims::TIME, 0.001),
    lit("min", Dims::TIME, 60.0),
    lit("h", Dims::TIME, 3600.0),
    lit("deg", Dims::ANGLE, 1.0),
    lit("rad", Dims::ANGLE, DEG_PER_RAD),
    lit("mph", Dims::SPEED, 0.44704),
    lit("kph", Dims::SPEED, 1.0 / 3.6),
    lit("kmh", Dims::SPEED, 1.0 / 3.6),
];

/// One unit name of a literal (`km`, `s2`: a trailing `2` squares it).
pub fn literal_unit(name: &str) -> Option<(Dims, f64)> {
    if let Some(u) = LITERAL_UNITS.iter().find(|u| u.name == name) {
        return Some((u.dims, u.factor));
    }
    let base = name.strip_suffix('2')?;
    let u = LITERAL_UNITS.iter().find(|u| u.name == base)?;
    Some((u.dims.times(u.dims), u.factor * u.factor))
}

/// A literal's whole unit from its parts: `km` alone, or `km` over `h`.
pub fn literal_measure(num: &str, den: Option<&str>) -> Option<Measure> {
    let (nd, nf) = literal_unit(num)?;
    let (dims, factor) = match den {
        None => (nd, nf),
        Some(d) => {
            let (dd, df) = literal_unit(d)?;
            (nd.over(dd), nf / df)
        }
    };
    Some(Measure {
        dims,
        factor,
        instant: false,
    })
}

/// A unit as written after a number or a column's type: one unit name or a quotient of two
/// (`km/h`).
pub fn parse_unit(text: &str) -> Option<Measure> {
    let mut parts = text.splitn(2, '/');
    let num = parts.next().unwrap_or_default();
    literal_measure(num, parts.next())
}

/// A value in base units written in the most readable unit of its dimensions: a speed also in
/// km/h, an angular rate also in rad/s, e.g. "50 m/s = 180 km/h".
pub fn readable(value: f64, m: Measure) -> String {
    let base = value * m.factor;
    let symbol = m.symbol();
    let first = match symbol.strip_prefix("frames") {
        Some(rest) if trim(value) == "1" => format!("1 frame{rest}"),
        _ => format!("{} {symbol}", trim(value)),
    };
    let also = match m.dims {
        Dims::SPEED => Some(format!("{} km/h", trim(base * 3.6))),
        Dims::ANGULAR_RATE => Some(format!("{} rad/s", trim(base / DEG_PER_RAD))),
        Dims::ANGLE => Some(format!("{} rad", trim(base / DEG_PER_RAD))),
        Dims::TIME if (m.factor - 1.0).abs() > 1e-12 => Some(format!("{} s", trim(base))),
        _ => None,
    };
    match also {
        Some(a) => format!("{first} = {a}"),
        None => first,
    }
}

/// A number with at most three decimals and no trailing zeros.
fn trim(v: f64) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn km_per_hour_is_a_speed_of_one_over_three_point_six() {
        let m = literal_measure("km", Some("h")).expect("km/h");
        assert_eq!(m.dims, Dims::SPEED);
        assert!((m.factor - 1.0 / 3.6).abs() < 1e-12);
        let rad = literal_measure("rad", Some("s")).expect("rad/s");
        assert_eq!(rad.dims, Dims::ANGULAR_RATE);
        assert!((0.3 * rad.factor - 17.188733853924695).abs() < 1e-9);
        let acc = literal_measure("m", Some("s2")).expect("m/s2");
        assert_eq!(acc.dims, Dims::ACCEL);
        assert_eq!(acc.factor, 1.0);
        assert!(literal_measure("furlong", None).is_none());
        assert!(literal_measure("m", Some("parsec")).is_none());
    }

    #[test]
    fn readable_says_a_speed_also_in_km_per_hour() {
        let v = Unit::MetrePerSecond.measure().expect("a quantity");
        assert_eq!(readable(50.0, v), "50 m/s = 180 km/h");
        let frames = Unit::Frame.measure().expect("a quantity").as_duration();
        assert_eq!(readable(3.0, frames), "3 frames of 0.1 s = 0.3 s");
        assert_eq!(readable(1.0, frames), "1 frame of 0.1 s = 0.1 s");
        assert_eq!(frames.describe(), "a duration (frames of 0.1 s)");
        assert_eq!(Dims::SPEED.over(Dims::TIME), Dims::ACCEL);
        assert_eq!(Measure::base(Dims::new(1, 0, 1)).symbol(), "m*deg");
    }
}
