//! The clamp search's filters against the search without them, on a
//! whole part's setups: here rather than in `clamp`, which a prepared
//! part's pieces depend on.

use crate::checks::admissibility::Scratch;
use crate::clamp::{Accumulator, ClampSearch};
use crate::enumerate::combinations::combinations_in;
use crate::enumerate::prepare::{prepare, PreparedPart};
use crate::input::Case;
use crate::setups::Setup;

/// Every setup of `bracket-arcs`, and its prepared part.
fn bracket_arcs() -> (PreparedPart, Vec<Setup>) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/cases/bracket-arcs.json"
    );
    let text = std::fs::read_to_string(path).expect("the bench case");
    let case: Case = serde_json::from_str(&text).expect("a valid case");
    let part = prepare(&case.part(), &case.kit, &case.params, case.units).expect("a valid part");
    let mut setups = Vec::new();
    for (_, combo) in combinations_in(part.segments().len(), 0..u64::MAX) {
        part.setups_of_combination(combo, |s| setups.push(*s));
    }
    (part, setups)
}

/// Every setup through `search` into `acc`.
fn run(search: &ClampSearch, setups: &[Setup], mut acc: Accumulator) -> Accumulator {
    let mut scratch = Scratch::default();
    for s in setups {
        search.process_setup(s, &mut acc, &mut scratch);
    }
    acc
}

/// The arcs' axis-line filter (`arc_reach`) drops no fixture: every
/// setup of `bracket-arcs` gives the same counts and the same
/// fixtures, bit for bit, as the search without it (every line across
/// each posed circle tried), with full counts (every admissible
/// fixture kept) and in top-10 mode.
#[test]
fn filtered_clamp_search_keeps_every_fixture() {
    let (part, setups) = bracket_arcs();
    assert!(setups.len() > 1000, "{}", setups.len());
    let filtered = part.clamp_search();
    let unfiltered = ClampSearch {
        reaches: &[],
        ..filtered
    };
    for acc in [Accumulator::new(0), Accumulator::top_k_mode(10)] {
        let want = run(&unfiltered, &setups, acc.clone());
        let got = run(&filtered, &setups, acc);
        assert_eq!(got.counts, want.counts);
        assert!(got.counts.candidates > 1000, "{:?}", got.counts);
        let (got, want) = (got.top.into_sorted(), want.top.into_sorted());
        assert!(!want.is_empty());
        assert_eq!(got, want);
    }
}
