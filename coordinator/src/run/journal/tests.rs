//! The journal's reading: deaths counted per part, alone or not, ended
//! sessions and other runs' sessions not counted, and damage ignored
//! without a panic.

use super::*;
use crate::output::messages::test_run_msg;

fn run_msg(digest: &str) -> RunMsg {
    test_run_msg("j", 3, digest)
}

const IDS: [&str; 3] = ["a", "b c", "d"];

fn session(run: &RunMsg) -> String {
    format!("session {}\n", serde_json::to_string(run).unwrap())
}

fn read(text: &str) -> History {
    History::read(text.as_bytes(), &run_msg("x"), &IDS)
}

fn deaths(h: &History) -> Vec<(usize, u32, u32)> {
    h.deaths
        .iter()
        .map(|(&i, d)| (i, d.times, d.alone))
        .collect()
}

#[test]
fn parts_in_flight_at_a_death_count_it_alone_or_not() {
    let s = session(&run_msg("x"));
    // Session 1 dies with parts 1 and 2 in flight; session 2 dies with
    // part 1 alone; session 3 ends in order with part 2 in flight.
    let text = format!(
        "{s}start 0 \"a\"\nstart 1 \"b c\"\ndone 0\nstart 2 \"d\"\n\
         {s}start 1 \"b c\"\n\
         {s}start 2 \"d\"\nend\n"
    );
    let h = read(&text);
    assert_eq!(deaths(&h), vec![(1, 2, 1), (2, 1, 0)]);
    assert_eq!((h.died, h.ignored), (2, 0));
}

#[test]
fn other_runs_and_lines_that_do_not_read_are_ignored() {
    let ours = session(&run_msg("x"));
    let theirs = session(&run_msg("y"));
    let text = format!(
        "start 0 \"a\"\n{theirs}start 0 \"a\"\n{ours}start 0 \"b c\"\nstart 7 \"a\"\nstart x \"a\"\n\
         done 2\nhello\nstart 1 \"b c\"\nstart 1 \"b c"
    );
    let h = read(&text);
    // Ignored: the line before any session, the other run's session and
    // its line, a part not at its place, one beyond the catalogue, an
    // index that is no number, a `done` of a part not started, a word,
    // and the last line cut off.
    assert_eq!(h.ignored, 9, "{h:?}");
    assert_eq!(deaths(&h), vec![(1, 1, 1)]);
}

#[test]
fn damaged_journals_never_panic_and_count_at_most_their_sessions() {
    let s = session(&run_msg("x"));
    let sound = format!("{s}start 0 \"a\"\ndone 0\nstart 1 \"b c\"\ndone 1\n{s}start 2 \"d\"\n");
    let mut seed = 31u64;
    for _ in 0..2_000 {
        let mut b = sound.clone().into_bytes();
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let at = (seed % b.len() as u64) as usize;
        match seed % 3 {
            0 => b[at] ^= 1 << ((seed >> 8) % 8),
            1 => b.truncate(at),
            _ => b[at] = (seed >> 16) as u8,
        }
        let h = History::read(b.as_slice(), &run_msg("x"), &IDS);
        assert!(h.died <= 2, "{h:?}");
        assert!(h.deaths.values().all(|d| d.times <= 2), "{h:?}");
    }
    // A line of a megabyte and more, and no newline at all.
    let long = format!("{s}start 0 {}\n{s}start 1 \"b c\"\n", "x".repeat(3 << 20));
    let h = read(&long);
    assert_eq!((h.ignored, deaths(&h)), (1, vec![(1, 1, 1)]));
    let h = History::read(&[0u8; 5 << 20][..], &run_msg("x"), &IDS);
    assert_eq!((h.ignored, h.died), (1, 0));
}
