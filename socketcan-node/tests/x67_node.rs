//! The X67BC4321-10 bus controller with its X67SM2436 module, driven as a master drives it: SDO for the
//! configuration, RPDO for the cyclic outputs, TPDO for the cyclic inputs (seed 002, 18.5, 18.11, 18.13,
//! 18.14).

use std::time::Duration;

use socketcan_node::node::storage::MemoryStorage;
use socketcan_node::sim::{SimError, SimNode};
use socketcan_node::x67::{self, X67Error};
use socketcan_node::{CanFrame, NodeConfig};

const ID: u8 = 4;

fn f(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

/// Output object 1: AbsPos01, MpGenControl01, MpGenMode01.
fn rpdo1(pos: i32, control: u16, mode: i8) -> CanFrame {
    let p = pos.to_le_bytes();
    let c = control.to_le_bytes();
    f(0x204, &[p[0], p[1], p[2], p[3], c[0], c[1], mode as u8, 0])
}

/// The last TPDO 1 (AbsPos01ActVal, MpGenStatus01, InputStatus) sent so far.
fn last_tpdo1(n: &SimNode) -> (i32, u16, u8) {
    let (_, fr) = *n.sent_on(0x184).last().expect("a TPDO 1");
    let d = fr.data8();
    (
        i32::from_le_bytes([d[0], d[1], d[2], d[3]]),
        u16::from_le_bytes([d[4], d[5]]),
        d[6],
    )
}

/// Configures axis 1 by SDO and brings it to Operation enabled by RPDO, in mode 1.
fn enabled() -> SimNode {
    let mut n = SimNode::new(ID, 1).unwrap();
    for (index, value) in [
        (0x2114u16, 100i64), // MaxSpeed01pos
        (0x2115, 10),        // MaxAcc01
        (0x2116, 10),        // MaxDec01
        (0x2110, 20),        // holding current
        (0x2111, 50),        // nominal current
        (0x2112, 100),       // maximum current
    ] {
        let size = if index >= 0x2114 { 2 } else { 1 };
        n.sdo_write(index, 0, &value.to_le_bytes()[..size]).unwrap();
    }
    n.nmt(0x01, ID);
    n.advance_ms(1100);
    // Shutdown, switch on (the switch-on takes up to 1.5 s: the motor identification), enable.
    for (control, ms) in [(0x0006u16, 100), (0x0007, 1500), (0x000F, 100)] {
        n.send(rpdo1(0, control, 1));
        n.advance_ms(ms);
    }
    let (_, status, _) = last_tpdo1(&n);
    assert_eq!(
        status & 0x006F,
        0x0027,
        "Operation enabled, status {status:#06x}"
    );
    n
}

#[test]
fn a_positioning_move_by_rpdo_ends_at_the_target() {
    let mut n = enabled();
    n.send(rpdo1(5000, 0x000F, 1));
    n.advance_ms(3000);
    let (pos, status, _) = last_tpdo1(&n);
    assert_eq!(pos, 5000);
    assert_ne!(status & 0x0400, 0, "target reached, status {status:#06x}");
    assert_eq!(n.sdo_read(0x2108, 0), Ok(5000i32.to_le_bytes().to_vec()));
    assert_eq!(n.sdo_read(0x2140, 0), Ok(vec![0x0F, 0x00]));
}

/// X67-18.11.1.17-05: the simulated bus controller is the X67BC4321-10, one of the controllers that
/// monitor the software limits, and the limits hold.
#[test]
fn x67_18_11_1_17_05_the_bus_controller_monitors_the_software_limits() {
    assert_eq!(x67::BUS_CONTROLLER, "X67BC4321-10");
    let dict = x67::dictionary(1).unwrap();
    assert_eq!(
        dict.entry(0x1008, 0).unwrap().value,
        b"X67BC4321-10 / X67SM2436".to_vec()
    );
    let mut n = enabled();
    n.sdo_write(0x2121, 0, &(-1000i32).to_le_bytes()).unwrap(); // PositionLimitMin01
    n.sdo_write(0x2122, 0, &1000i32.to_le_bytes()).unwrap(); // PositionLimitMax01
                                                             // A target beyond the limit is held back (bit 11); one inside is reached.
    n.send(rpdo1(5000, 0x000F, 1));
    n.advance_ms(1000);
    let (pos, status, _) = last_tpdo1(&n);
    assert!(pos <= 1000, "{pos}");
    assert_ne!(
        status & 0x0800,
        0,
        "bit 11 internal limit, status {status:#06x}"
    );
    n.send(rpdo1(800, 0x000F, 1));
    n.advance_ms(3000);
    let (pos, status, _) = last_tpdo1(&n);
    assert_eq!(pos, 800);
    assert_eq!(status & 0x0800, 0, "status {status:#06x}");
}

/// X67-18.13-01: the Ramp model runs at an X2X cycle down to 250 µs; a shorter one is refused.
#[test]
fn x67_18_13_01_x2x_cycle_of_250_us_and_not_below() {
    let refused = SimNode::build(
        NodeConfig::new(ID),
        1,
        Duration::from_micros(249),
        Box::new(MemoryStorage::default()),
    );
    assert!(matches!(refused, Err(SimError::X67(X67Error::Cycle(249)))));
    assert!(X67Error::Cycle(249).to_string().contains("250 µs"));
    let mut n = SimNode::build(
        NodeConfig::new(ID),
        1,
        Duration::from_micros(250),
        Box::new(MemoryStorage::default()),
    )
    .unwrap();
    n.nmt(0x01, ID);
    n.advance_ms(1500);
    // 40 input changes, one per X2X cycle: every one reaches the bus, none lost or stale.
    let mut seen = Vec::new();
    for k in 0..40u8 {
        let bits = k % 64;
        n.sdo_write(0x5F00, 1, &[bits]).unwrap();
        n.advance(Duration::from_micros(250));
        seen.push(last_tpdo1(&n).2);
    }
    assert_eq!(seen, (0..40u8).collect::<Vec<_>>());
}

/// X67-18.14-01: at a 250 µs cycle an edge on DI1 appears in InputStatus within one cycle.
#[test]
fn x67_18_14_01_inputs_updated_every_250_us_cycle() {
    let mut n = SimNode::build(
        NodeConfig::new(ID),
        1,
        Duration::from_micros(250),
        Box::new(MemoryStorage::default()),
    )
    .unwrap();
    n.nmt(0x01, ID);
    n.advance_ms(1500);
    let t = n.elapsed();
    n.sdo_write(0x5F00, 1, &[0x01]).unwrap();
    n.advance(Duration::from_micros(250));
    let (when, fr) = *n.sent_on(0x184).last().unwrap();
    assert_eq!(fr.data()[6], 0x01);
    assert!(
        when > t && when - t <= Duration::from_micros(250),
        "{:?}",
        when - t
    );
    assert_eq!(n.sdo_read(0x2008, 0), Ok(vec![0x01]));
}

/// X67-18.5.2-02, X67-18.5.2-04, X67-18.5.2-05 on the wire: input object 1 is AbsPos01ActVal
/// little-endian in bytes 0–3, MpGenStatus01 in 4–5, InputStatus in 6, 0x00 in byte 7, DLC 8; input
/// object 2 (X67-18.5.2-03) carries axis 2 with bytes 6–7 0x00. Byte 7 of an output object is ignored.
#[test]
fn x67_18_5_2_input_objects_byte_by_byte() {
    let mut n = enabled();
    // Garbage in the unused output byte 7 changes nothing.
    let mut move_to = rpdo1(0x0001_2345, 0x000F, 1).data8();
    move_to[7] = 0xA5;
    n.send(f(0x204, &move_to));
    n.advance_ms(25_000);
    n.sdo_write(0x5F00, 1, &[0x01]).unwrap(); // DI1 high
    n.advance_ms(100);
    let (_, t1) = *n.sent_on(0x184).last().unwrap();
    let (_, t2) = *n.sent_on(0x284).last().unwrap();
    let status = u16::from_le_bytes([t1.data()[4], t1.data()[5]]);
    assert_ne!(status & 0x0400, 0, "target reached, status {status:#06x}");
    let [s0, s1] = status.to_le_bytes();
    assert_eq!(t1.data(), &[0x45, 0x23, 0x01, 0x00, s0, s1, 0x01, 0x00]);
    // Axis 2 never moved: position 0, its status (Switch on disabled 0x0240 and what the model adds).
    let st2 = u16::from_le_bytes([t2.data()[4], t2.data()[5]]);
    assert_eq!(
        st2 & 0x006F,
        0x0040,
        "axis 2 in Switch on disabled, {st2:#06x}"
    );
    let [a0, a1] = st2.to_le_bytes();
    assert_eq!(t2.data(), &[0, 0, 0, 0, a0, a1, 0x00, 0x00]);
    assert_eq!(n.sdo_read(0x2108, 0), Ok(vec![0x45, 0x23, 0x01, 0x00]));
}

/// Module m ≥ 2's registers are named as module 1's with `_Mm` appended, each module's simulation
/// inputs after the module; module 1 keeps the description's names. A description of the whole node
/// (written by `x67-node --write-description`) names every object once.
#[test]
fn each_module_names_its_objects_once() {
    let dict = x67::dictionary(3).unwrap();
    let at = |name: &str| dict.lookup(name).map(|a| (a.index, a.sub));
    assert_eq!(at("InputStatus"), Ok((0x2008, 0)));
    assert_eq!(at("InputStatus_M2"), Ok((0x2308, 0)));
    assert_eq!(at("InputStatus_M3"), Ok((0x2608, 0)));
    assert_eq!(at("ConfigOutput03a_M2"), Ok((0x2410, 0)));
    assert!(at("InputStatus_M4").is_err());
    assert_eq!(
        at("Simulation inputs module 2.Supply voltage [0.1 V]"),
        Ok((0x5F01, 2))
    );
    assert_eq!(
        dict.object(0x5F00).unwrap().name,
        "Simulation inputs module 1"
    );
    // Written and read back as an EDS, the names are the same.
    let desc = x67::description(3).unwrap();
    let back = od::eds::read(od::eds::write_eds(&desc).as_bytes(), "node.eds").unwrap();
    assert_eq!(
        back.dictionary.lookup("InputStatus_M3").map(|a| a.index),
        Ok(0x2608)
    );
    assert_eq!(back.dictionary.len(), dict.len());
}
