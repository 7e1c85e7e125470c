//! Workspace-level integration tests of fixplan: the command line end to
//! end (`solve`, `run`, `show`, `export`, `render`, `study`), MCAP files read
//! back by our reader and by Python's, resume after SIGKILL, and the cluster
//! (coordinator plus worker processes on this host over zenoh and iceoryx2,
//! failures, network namespaces). The tests run `fixplan-it`, this package's
//! build of the `fixplan` command line.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

use fixplan_catalog::{
    Catalog, CatalogPart, InvalidPolygon, KitSpec, PartError, PartErrorKind, PolygonProblem,
    PolygonRole,
};
use fixplan_coordinator::{TOPIC_FIXTURES, TOPIC_SCENE};
use fixplan_core::parts::PolygonError;
use fixplan_core::{Case, Part, Units};
use std::path::{Path, PathBuf};

/// A case file of `examples/cases`.
pub fn case(name: &str) -> Case {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/cases")
        .join(name);
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// A valid inline catalogue entry with this outline.
pub fn part(id: &str, outline: Vec<[f64; 2]>) -> CatalogPart {
    CatalogPart {
        id: id.into(),
        file: None,
        part: Ok(Part::polygon(&outline)),
        warnings: vec![],
        quantity: 1.0,
        top_k: None,
        wrenches: None,
    }
}

/// Small parts of very different sizes, one the catalogue found broken,
/// one invalid polygon, one too small to hold.
pub fn catalog() -> (Catalog, KitSpec) {
    let c = case("rectangle-mm.json");
    let mut rect = part("rect", vec![]);
    rect.part = Ok(c.part());
    let parts = vec![
        rect,
        part(
            "ell",
            vec![
                [0.0, 0.0],
                [90.0, 0.0],
                [90.0, 30.0],
                [30.0, 30.0],
                [30.0, 70.0],
                [0.0, 70.0],
            ],
        ),
        part(
            "bowtie",
            vec![[0.0, 0.0], [50.0, 50.0], [50.0, 0.0], [0.0, 50.0]],
        ),
        CatalogPart {
            part: Err(PartError {
                id: "broken".into(),
                file: None,
                kind: PartErrorKind::Invalid {
                    problem: InvalidPolygon {
                        polygon: PolygonRole::Outline,
                        problem: PolygonProblem::Core {
                            error: PolygonError::SelfIntersection {
                                first: 0,
                                second: 2,
                                x: 25.0,
                                y: 25.0,
                            },
                            units: Units::Mm,
                        },
                    },
                    read: Box::new(Part {
                        outline: [[0.0, 0.0], [50.0, 50.0], [50.0, 0.0], [0.0, 50.0]]
                            .map(Into::into)
                            .to_vec(),
                        holes: vec![],
                        access: vec![],
                    }),
                },
            }),
            ..part("broken", vec![])
        },
        part("tiny", vec![[0.0, 0.0], [3.0, 0.0], [0.0, 3.0]]),
        // A hexagon with arcs (SPEC 8): a convex arc, a concave one and a
        // half-round end, so every transport and resume path carries them.
        CatalogPart {
            part: Ok(Part {
                outline: [
                    [30.0, 0.0, 0.0],
                    [70.0, 0.0, -0.2],
                    [95.0, 40.0, 0.0],
                    [70.0, 80.0, 0.0],
                    [30.0, 80.0, 0.25],
                    [5.0, 40.0, 0.0],
                ]
                .map(Into::into)
                .to_vec(),
                holes: vec![],
                access: vec![],
            }),
            ..part("hex", vec![])
        },
    ];
    let cat = Catalog {
        name: "mem".into(),
        units: Units::Mm,
        source: PathBuf::from("mem"),
        parts,
    };
    let spec = KitSpec {
        name: "case-kit".into(),
        kit: c.kit.clone(),
        params: c.params.clone(),
    };
    (cat, spec)
}

/// The output of a command that must have succeeded; both streams shown
/// if it did not.
pub fn ok(out: std::process::Output) -> std::process::Output {
    assert!(
        out.status.success(),
        "exit {:?}\nstdout:\n{}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The fixtures channel of a complete results file, part by part: what
/// must be byte-identical however the run was split.
pub fn fixtures_channel(path: &Path) -> Vec<Vec<u8>> {
    channels(path).into_iter().map(|(f, _)| f).collect()
}

/// The fixtures and scene messages of a complete results file, part by
/// part: the channels that do not depend on timing.
pub fn channels(path: &Path) -> Vec<(Vec<u8>, Vec<u8>)> {
    let f = fixplan_coordinator::ResultsFile::open(path).unwrap();
    let mut v = Vec::new();
    let c = f.for_each_part(|_, m| {
        v.push((
            m.get(TOPIC_FIXTURES).unwrap().to_vec(),
            m.get(TOPIC_SCENE).unwrap().to_vec(),
        ));
        true
    });
    assert!(c.unwrap().complete);
    v
}
