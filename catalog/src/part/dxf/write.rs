//! Writing a part as a DXF file any CAD program opens.

use super::super::outline::straight;
use fixplan_core::{Part, Units, Vertex};

/// Writes a part as an AutoCAD 2000 (AC1015) DXF: one closed LWPOLYLINE on
/// layer `PART` for the outline (arcs as bulges, group code 42), one on
/// layer `HOLES` per hole, in order (the reader takes loops inside the
/// outline as holes, in file order), and one on layer `ACCESS` per access
/// constraint, `$INSUNITS` set from `units`.
/// Numbers are written in Rust's shortest round-trip form, so reading the
/// file back gives the same part.
pub fn write_dxf(part: &Part, units: Units) -> String {
    let insunits = match units {
        Units::Mm => 4,
        Units::In => 1,
    };
    let mut s = String::new();
    let mut pair = |code: i32, value: &str| {
        s.push_str(&format!("{code:>3}\n{value}\n"));
    };
    pair(0, "SECTION");
    pair(2, "HEADER");
    pair(9, "$ACADVER");
    pair(1, "AC1015");
    pair(9, "$INSUNITS");
    pair(70, &insunits.to_string());
    pair(0, "ENDSEC");
    pair(0, "SECTION");
    pair(2, "ENTITIES");
    let access: Vec<Vec<Vertex>> = part.access.iter().map(|a| straight(a.clone())).collect();
    let polys = std::iter::once(("PART", &part.outline))
        .chain(part.holes.iter().map(|h| ("HOLES", h)))
        .chain(access.iter().map(|a| ("ACCESS", a)));
    for (handle, (layer, pts)) in (0x100..).zip(polys) {
        pair(0, "LWPOLYLINE");
        pair(5, &format!("{handle:X}"));
        pair(100, "AcDbEntity");
        pair(8, layer);
        pair(100, "AcDbPolyline");
        pair(90, &pts.len().to_string());
        pair(70, "1");
        for p in pts.iter() {
            pair(10, &format!("{:?}", p.x));
            pair(20, &format!("{:?}", p.y));
            if p.is_arc() {
                pair(42, &format!("{:?}", p.bulge));
            }
        }
    }
    pair(0, "ENDSEC");
    pair(0, "EOF");
    s
}
