//! Two virtual SMD23K-B on one chain, driven the way an EtherCAT master drives them: count, address,
//! read the SII identity, configure SyncManagers and FMMUs, bring them to Op, then exchange process
//! data with one LRW per cycle — a Relative move on each ends with Move_Complete at the target.

mod common;

use common::master::*;
use ds402::smd::indexer::{cmd0, stat0, stat1, Outputs};
use ethercat_slave::esc::al::state;
use ethercat_slave::esc::cmd;
use ethercat_slave::master::SimChain;
use ethercat_slave::master::{decode_outputs, encode_inputs, encode_outputs};
use ethercat_slave::smd::binding::Device;

/// A clone of a chain is a second chain in the same state that runs on its own: the clone goes to
/// Pre-Op while the original stays in Init (SMD-T2-007), then the original goes to Pre-Op too.
#[test]
fn a_cloned_chain_runs_on_its_own() {
    let mut a = SimChain::new(Device::Smd23kB, 2).unwrap();
    configure(&mut a);
    let mut b = a.clone();
    assert_eq!(request(&mut b, state::PREOP), 2);
    let al = |c: &mut SimChain| reg(c, cmd::BRD, 0, 0x0130, vec![0; 2]).data[0];
    assert_eq!(al(&mut b), state::PREOP);
    assert_eq!(al(&mut a), state::INIT);
    assert_eq!(request(&mut a, state::PREOP), 2);
    assert_eq!(al(&mut a), state::PREOP);
}

#[test]
fn two_units_from_init_to_a_relative_move() {
    let mut c = SimChain::new(Device::Smd23kB, 2).unwrap();
    assert_eq!(reg(&mut c, cmd::BRD, 0, 0, vec![0; 2]).wkc, 2);
    configure(&mut c);
    // The SII identity through the EEPROM interface of unit 2: serial number 2.
    fpwr(&mut c, 1, 0x0504, 0x0Eu32.to_le_bytes().to_vec());
    fpwr(&mut c, 1, 0x0502, 0x0100u16.to_le_bytes().to_vec());
    assert_eq!(fprd(&mut c, 1, 0x0508, 4).0, 2u32.to_le_bytes());
    for s in [state::PREOP, state::SAFEOP] {
        assert_eq!(request(&mut c, s), 2);
        let r = reg(&mut c, cmd::BRD, 0, 0x0130, vec![0; 2]);
        assert_eq!(r.data[0], s, "both in state {s}");
    }
    // Safe-Op: inputs flow, PreOp_SafeOp is set; outputs are not acted on.
    let idle = Outputs::default();
    lrw(&mut c, &[idle, idle]);
    let (wkc, inputs) = lrw(&mut c, &[idle, idle]);
    assert_eq!(
        wkc, 6,
        "each unit: the input FMMU read (1) and the output FMMU write (2)"
    );
    assert_ne!(inputs[0].status1 & stat1::PREOP_SAFEOP, 0);
    assert_eq!(request(&mut c, state::OP), 2);
    let mut o = [Outputs {
        cmd0: cmd0::PRESET_POSITION,
        cmd1: 0x8000,
        velocity: 10_000,
        acceleration: 100,
        deceleration: 100,
        ..idle
    }; 2];
    lrw(&mut c, &o);
    o[0].cmd0 = 0;
    o[1].cmd0 = 0;
    lrw(&mut c, &o);
    o[0] = Outputs {
        cmd0: cmd0::RELATIVE_MOVE,
        position: 5_000,
        ..o[0]
    };
    o[1] = Outputs {
        cmd0: cmd0::RELATIVE_MOVE,
        position: -2_000,
        ..o[1]
    };
    let mut last = Vec::new();
    for _ in 0..5_000 {
        let (wkc, inputs) = lrw(&mut c, &o);
        assert_eq!(wkc, 6, "each unit: read 1 + write 2");
        let done = inputs.iter().all(|i| i.status0 & stat0::MOVE_COMPLETE != 0);
        last = inputs;
        if done {
            break;
        }
    }
    assert_eq!(
        (last[0].motor_position, last[1].motor_position),
        (5_000, -2_000)
    );
    assert_eq!(last[0].status1 & stat1::PREOP_SAFEOP, 0, "in Op");
    // The codecs used above round-trip.
    assert_eq!(decode_outputs(&encode_outputs(&o[1])), o[1]);
    assert_eq!(
        encode_inputs(&c.unit(0).unwrap().inputs())[4..8],
        5_000i32.to_le_bytes()
    );
}

/// The chain's one clock: a cycle runs only when `poll_timeout` has passed (a frame never runs one),
/// over the whole time since the last; the Distributed Clocks count from the chain's power-on; a
/// stalled host gets one cycle over the gap and the next a cycle later.
#[test]
fn the_chain_runs_its_cycle_when_its_poll_timeout_has_passed() {
    let t0 = std::time::Instant::now();
    let ms = std::time::Duration::from_millis;
    let chain = ethercat_slave::smd::SmdChain::new(Device::Smd23kB, 1, ms(10), t0).unwrap();
    let mut c = SimChain { chain, now: t0 };
    let model_time = |c: &SimChain| c.unit(0).unwrap().indexer().time();
    assert_eq!(c.cycle_time(), ms(10));
    assert_eq!(c.poll_timeout(), Some(t0 + ms(10)));
    c.now = t0 + ms(4);
    assert_eq!(reg(&mut c, cmd::BRD, 0, 0x0130, vec![0; 2]).wkc, 1);
    assert_eq!(c.time_ns(), 4_000_000, "the frame's time");
    assert_eq!(model_time(&c), ms(0), "a frame runs no cycle");
    c.chain.handle_timeout(t0 + ms(9));
    assert_eq!(model_time(&c), ms(0), "not due yet");
    assert_eq!(c.poll_timeout(), Some(t0 + ms(10)));
    c.chain.handle_timeout(t0 + ms(10));
    assert_eq!(model_time(&c), ms(10));
    assert_eq!(c.poll_timeout(), Some(t0 + ms(20)));
    c.chain.handle_timeout(t0 + ms(23));
    assert_eq!(
        model_time(&c),
        ms(23),
        "the cycle due at 20 ms ran at 23 ms, over 13 ms"
    );
    assert_eq!(c.poll_timeout(), Some(t0 + ms(30)), "the period holds");
    c.chain.handle_timeout(t0 + ms(5_000));
    assert_eq!(model_time(&c), ms(5_000));
    assert_eq!(
        c.poll_timeout(),
        Some(t0 + ms(5_010)),
        "after a stall: a cycle from now"
    );
    assert_eq!(c.time_ns(), 5_000_000_000);
    // An earlier time than the chain has seen does not move its clocks back.
    c.now = t0 + ms(1);
    assert_eq!(reg(&mut c, cmd::BRD, 0, 0x0130, vec![0; 2]).wkc, 1);
    assert_eq!(c.time_ns(), 5_000_000_000);
}

/// The model is told each AL state the unit enters (its own view: SMD-R6-072 PreOp_SafeOp, commands
/// only in Op): Init at power-up, then Pre-Op, Safe-Op, Op, and back through Init.
#[test]
fn the_model_follows_the_al_state() {
    use ds402::smd::indexer::NetworkState;
    let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
    let seen = |c: &SimChain| c.unit(0).unwrap().indexer().network_state();
    assert_eq!(seen(&c), NetworkState::Init);
    configure(&mut c);
    for (s, network) in [
        (state::PREOP, NetworkState::PreOp),
        (state::SAFEOP, NetworkState::SafeOp),
        (state::OP, NetworkState::Op),
        (state::INIT, NetworkState::Init),
        (state::PREOP, NetworkState::PreOp),
    ] {
        if s == state::OP {
            lrw(&mut c, &[Outputs::default()]);
        }
        assert_eq!(request(&mut c, s), 1);
        c.cycle(std::time::Duration::from_millis(1));
        assert_eq!(seen(&c), network, "state {s}");
    }
}
