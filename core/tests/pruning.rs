//! How tight the setup pruning is (issue 15): on the polygon bench cases
//! the search solves at most three poses per setup it keeps. Counts, not
//! times, so the test is exact on any machine; completeness is the brute
//! force tests' job.
#![allow(clippy::unwrap_used)] // a test stops at the first surprise

fn case(name: &str) -> fixplan_core::PreparedPart {
    let path = format!(
        "{}/../examples/cases/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(path).expect("bench case in examples/cases");
    let mut case: fixplan_core::Case = serde_json::from_str(&text).expect("valid case");
    case.params.top_k = 0;
    fixplan_core::prepare(&case.part(), &case.kit, &case.params, case.units).expect("valid case")
}

#[test]
fn polygon_bench_cases_solve_at_most_three_poses_per_setup() {
    for name in [
        "gluegun-28",
        "housing-57",
        "rectangle-mm",
        "bracket-flattened",
    ] {
        let p = case(name);
        let done = p.enumerate(
            0..p.combination_count(),
            fixplan_core::EnumerateOptions::this_thread(),
        );
        let (res, profile) = (done.result, done.profile);
        let setups = res.counts.setups;
        let poses = profile.search.pose_solutions;
        assert!(setups > 0, "{name}: no setup");
        assert!(
            poses <= 3 * setups,
            "{name}: {poses} poses solved for {setups} setups"
        );
        // Every setup comes from a solved pose.
        assert!(poses >= setups, "{name}: {poses} < {setups}");
    }
}
