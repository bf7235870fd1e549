//! The indexer on the device contract: when its next process-data exchange is due
//! ([`Indexer::poll_timeout`]), and the inputs whose instant it acts on (the SYNC0 event, the
//! SyncManager watchdog).

mod smd_rig;

use std::time::{Duration, Instant};

use ds402::smd::config::{Configuration, EncoderKind};
use ds402::smd::indexer::{cmd0, stat0, Indexer, Outputs};
use smd_rig::{Rig, MS};

fn us(n: u64) -> Duration {
    Duration::from_micros(n)
}

/// No exchange is due before the start; after it, one period after the last exchange: started at
/// t0 with 2 ms, due at t0 + 2 ms; exchanged then, due at t0 + 4 ms; exchanged late at t0 + 5 ms,
/// due at t0 + 7 ms; an exchange at an earlier instant (t0 + 3 ms) moves nothing back; a clockless
/// cycle of 1 ms works out t0 + 6 ms as its instant, due at t0 + 8 ms; a power cycle keeps it.
#[test]
fn poll_timeout_is_the_last_exchange_plus_the_period() {
    let t0 = Instant::now();
    let ms = Duration::from_millis;
    let mut ix = Indexer::new(EncoderKind::Incremental, Configuration::default());
    assert_eq!(ix.poll_timeout(), None);
    ix.cycle(Outputs::default(), MS);
    assert_eq!(ix.poll_timeout(), None, "a clockless cycle starts nothing");
    assert_eq!(ix.last_exchange(), None);

    ix.start(t0, ms(2));
    assert_eq!(ix.last_exchange(), Some(t0));
    assert_eq!(ix.poll_timeout(), Some(t0 + ms(2)));
    ix.exchange(t0 + ms(2), Outputs::default());
    assert_eq!(ix.poll_timeout(), Some(t0 + ms(4)));
    ix.exchange_held(t0 + ms(5));
    assert_eq!(ix.last_exchange(), Some(t0 + ms(5)));
    assert_eq!(ix.poll_timeout(), Some(t0 + ms(7)));
    ix.exchange(t0 + ms(3), Outputs::default());
    assert_eq!(ix.poll_timeout(), Some(t0 + ms(7)), "never back");
    ix.cycle(Outputs::default(), ms(1));
    assert_eq!(ix.last_exchange(), Some(t0 + ms(6)));
    assert_eq!(ix.poll_timeout(), Some(t0 + ms(8)));
    ix.power_cycle();
    assert_eq!(ix.poll_timeout(), Some(t0 + ms(8)), "the exchanges go on");
}

/// A clockless run and a run on the clock at the same instants give the same inputs, and the
/// clockless run's instants are the start plus its time steps (1 ms, then 250 µs).
#[test]
fn a_clockless_cycle_works_out_its_instant() {
    let t0 = Instant::now();
    let mut by_dt = Indexer::new(EncoderKind::Incremental, Configuration::default());
    by_dt.start(t0, MS);
    let mut by_now = by_dt.clone();
    let out = Outputs {
        cmd0: cmd0::PRESET_POSITION,
        ..Outputs::default()
    };
    assert_eq!(by_dt.cycle(out, MS), by_now.exchange(t0 + MS, out));
    assert_eq!(
        by_dt.cycle_held(us(250)),
        by_now.exchange_held(t0 + us(1_250))
    );
    assert_eq!(by_dt.last_exchange(), Some(t0 + us(1_250)));
    assert_eq!(by_dt.poll_timeout(), Some(t0 + us(2_250)));
}

/// A DC_Sync unit (CFG_Word_1 = 0x0043) waiting for SYNC0 at 1 ms updates, the move commanded at
/// the exchange of t.
fn waiting_for_sync0() -> Rig {
    let mut r = Rig::new();
    r.ix.write_config(r.now(), 2, 0x0043);
    r.out.cmd1 = ds402::smd::indexer::cmd1::ENABLE_DRIVER;
    r.out.velocity = 10_000;
    r.out.acceleration = 10;
    r.out.deceleration = 10;
    r.command(cmd0::PRESET_POSITION);
    r.command(0);
    r.out.position = 10_000;
    r.command(cmd0::RELATIVE_MOVE);
    assert_ne!(r.s0() & stat0::STOPPED, 0, "waits for SYNC0");
    r
}

/// SMD-R1-022: the 520 µs of DC_Sync count from the SYNC0 event's instant. The move is commanded
/// at the exchange of t; SYNC0 at t + 300 µs starts it at t + 820 µs, so the exchange of
/// t + 1 ms reports motion; SYNC0 at t + 500 µs starts it at t + 1,020 µs: still Stopped at
/// t + 1 ms, moving at t + 2 ms. SYNC0 reported at t − 300 µs (before the exchange that took the
/// move) counts from that exchange: started at t + 520 µs, moving at t + 1 ms.
#[test]
fn smd_r1_022_the_start_delay_counts_from_the_sync0_instant() {
    for (at, moving_at_1ms) in [(300i64, true), (500, false), (-300, true)] {
        let mut r = waiting_for_sync0();
        let t = r.now();
        let event = if at >= 0 {
            t + us(at as u64)
        } else {
            t - us(at.unsigned_abs())
        };
        r.ix.sync0_event(event);
        let s0 = r.ix.exchange_held(t + MS).status0;
        assert_eq!(s0 & stat0::STOPPED == 0, moving_at_1ms, "SYNC0 at {at} µs");
        let s0 = r.ix.exchange_held(t + 2 * MS).status0;
        assert_eq!(s0 & stat0::STOPPED, 0, "SYNC0 at {at} µs: moving at 2 ms");
    }
}

/// SMD-R1-035, SMD-R6-056: a SyncManager watchdog expiring between two exchanges stops the move
/// where it is at the expiry: as if the unit had exchanged at that instant and then expired.
/// The motor has moved on since the last exchange, and stands still after it.
#[test]
fn smd_r1_035_r6_056_the_watchdog_stops_a_move_at_its_instant() {
    let mut r = Rig::ready();
    r.out.position = 100_000;
    r.command(cmd0::RELATIVE_MOVE);
    for _ in 0..300 {
        r.cycle();
    }
    let t = r.now();
    let before = r.pos();
    let mut exchanged = r.ix.clone();
    r.ix.sm_watchdog_expired(t + us(500));
    exchanged.exchange_held(t + us(500));
    exchanged.sm_watchdog_expired(t + us(500));
    let i = r.ix.exchange_held(t + MS);
    assert_eq!(i, exchanged.exchange_held(t + MS));
    assert!(
        i.motor_position > before,
        "{} after {before}",
        i.motor_position
    );
    assert_ne!(i.status0 & stat0::STOPPED, 0);
    assert_ne!(i.status0 & stat0::POSITION_INVALID, 0);
    assert_eq!(
        r.ix.exchange_held(t + 2 * MS).motor_position,
        i.motor_position
    );
}
