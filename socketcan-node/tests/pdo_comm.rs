//! PDOs and the communication objects of a node from the example I/O device (examples/io-device.eds,
//! node-ID 5), in process on a simulated clock: the rules of writes to 0x1005–0x1016 and the PDO
//! parameters with their exact abort codes, the mapping procedure, and the PDO engine's frames and
//! times on the wire.
//!
//! The device's PDOs as the description sets them: RPDO 1 on 0x205 (type 255: 0x6200:01, 0x6200:02),
//! RPDO 2 on 0x305 (type 1: 0x6411:01, 0x6411:02), TPDO 1 on 0x185 (type 255: 0x6000:01, 0x6000:02),
//! TPDO 2 on 0x285 (type 1: 0x6401:01, 0x6401:02).

use std::path::Path;
use std::time::{Duration, Instant};

use od::abort::AbortCode;
use od::dict::{Address, Dictionary};
use od::hook::DeviceHook;
use od::object::AccessType;
use socketcan_node::node::pdo::{Direction, MapEntry, PdoConfig};
use socketcan_node::node::storage::MemoryStorage;
use socketcan_node::node::{Device, DeviceError};
use socketcan_node::sim::SimNode;
use socketcan_node::{CanFrame, NmtState, Node, NodeConfig};

const ID: u8 = 5;

/// The device behind the node: its digital inputs 0x6000:01 and :02, which it reports when the test
/// says (`due`), the instant the node compares its event-driven TPDOs with what they sent last; at
/// that instant they become `next` where the test set it. At a SYNC the device first runs a timeout
/// due by then by itself, as a drive runs its control ticks up to the SYNC. The dictionary holds
/// everything else.
#[derive(Debug, Default)]
struct Io {
    inputs: [u8; 2],
    due: Option<Instant>,
    next: Option<[u8; 2]>,
}

impl DeviceHook for Io {
    fn owns(&self, index: u16) -> bool {
        index == 0x6000
    }

    fn read(&self, at: Address, out: &mut [u8; 8]) -> Option<usize> {
        out[0] = *self.inputs.get(usize::from(at.sub).checked_sub(1)?)?;
        Some(1)
    }

    fn write(&mut self, _: Address, _: &[u8], _: Instant) -> Result<(), AbortCode> {
        Ok(())
    }
}

impl Device for Io {
    fn handle_timeout(&mut self, _: Instant) {
        self.due = None;
        if let Some(v) = self.next.take() {
            self.inputs = v;
        }
    }

    fn sync(&mut self, now: Instant) {
        if self.due.is_some_and(|t| t <= now) {
            self.handle_timeout(now);
        }
    }

    fn poll_timeout(&self) -> Option<Instant> {
        self.due
    }

    fn errors(&self, _: &mut Vec<DeviceError>) {}

    fn reset(&mut self, _: Instant) {
        self.due = None;
        self.next = None;
    }
}

/// The example I/O device's dictionary.
fn io_device() -> Dictionary {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/io-device.eds");
    let (_, mut descriptions) = od::load::load(&path).unwrap();
    descriptions.remove(0).dictionary
}

/// Node 5 of `dict`, booted at time zero.
fn node_of(dict: Dictionary) -> SimNode<Io> {
    let t0 = Instant::now();
    let node = Node::new(NodeConfig::new(ID), dict, Io::default(), t0).unwrap();
    SimNode::boot(node, t0, Box::new(MemoryStorage::default()))
}

fn node() -> SimNode<Io> {
    node_of(io_device())
}

fn f(id: u16, data: &[u8]) -> CanFrame {
    CanFrame::new(id, data).unwrap()
}

fn u32w(n: &mut SimNode<Io>, index: u16, sub: u8, value: u32) -> Result<(), u32> {
    n.sdo_write(index, sub, &value.to_le_bytes())
}

/// An expedited download of `data` to `index:sub`: every frame the node sends in answer.
fn download(n: &mut SimNode<Io>, index: u16, sub: u8, data: &[u8]) -> Vec<CanFrame> {
    let i = index.to_le_bytes();
    let mut d = [
        0x23 | ((4 - data.len() as u8) << 2),
        i[0],
        i[1],
        sub,
        0,
        0,
        0,
        0,
    ];
    d[4..4 + data.len()].copy_from_slice(data);
    n.send(f(0x605, &d))
}

/// The SDO server's confirmation of a download to `index:sub` (CiA 301 §7.2.4.3.3: scs 3).
fn confirmed(index: u16, sub: u8) -> CanFrame {
    let i = index.to_le_bytes();
    f(0x585, &[0x60, i[0], i[1], sub, 0, 0, 0, 0])
}

/// The device reports inputs `v` now: the frames the node sends at this instant.
fn inputs(n: &mut SimNode<Io>, v: [u8; 2]) -> Vec<CanFrame> {
    let now = n.now;
    let app = n.node.app_mut();
    app.inputs = v;
    app.due = Some(now);
    n.stall(Duration::ZERO)
}

fn sync(n: &mut SimNode<Io>) -> Vec<CanFrame> {
    n.send(f(0x080, &[]))
}

fn ms(v: u64) -> Duration {
    Duration::from_millis(v)
}

/// CiA 301 §7.5.2.17: the COB-ID EMCY takes a new 11-bit CAN-ID, but not a restricted one (§7.3.5:
/// 0x701–0x77F is NMT error control) nor a 29-bit identifier (bit 29): 0x06090030. The next EMCY
/// goes out on the new CAN-ID.
#[test]
fn the_emcy_cob_id_takes_a_new_can_id_but_no_restricted_one() {
    let mut n = node();
    assert_eq!(u32w(&mut n, 0x1014, 0, 0x0000_0705), Err(0x0609_0030));
    assert_eq!(u32w(&mut n, 0x1014, 0, 0x2000_00A5), Err(0x0609_0030));
    assert_eq!(n.sdo_read(0x1014, 0), Ok(vec![0x85, 0, 0, 0]));
    assert_eq!(u32w(&mut n, 0x1014, 0, 0x0000_00A5), Ok(()));
    assert_eq!(n.sdo_read(0x1014, 0), Ok(vec![0xA5, 0, 0, 0]));
    // An RPDO one byte short of its two: EMCY 0x8210 (generic and communication error, 0x11) with
    // the COB-ID, the length received and the length mapped.
    n.nmt(0x01, ID);
    assert_eq!(
        n.send(f(0x205, &[0x01])),
        vec![f(0x0A5, &[0x10, 0x82, 0x11, 0x05, 0x02, 1, 2, 0])]
    );
}

/// CiA 301 §7.5.2.35: the CAN-ID of a PDO that exists (bit 31 clear) cannot change (0x06090030); the
/// rule looks at the PDO written, an RPDO or a TPDO of the same number.
#[test]
fn a_pdo_can_id_changes_only_while_that_pdo_is_invalid() {
    let mut n = node();
    // RPDO 1 invalid, TPDO 1 valid.
    assert_eq!(u32w(&mut n, 0x1400, 1, 0x8000_0205), Ok(()));
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x0000_0186), Err(0x0609_0030));
    assert_eq!(u32w(&mut n, 0x1400, 1, 0x8000_0206), Ok(()));
    // RPDO 1 valid, TPDO 1 invalid.
    assert_eq!(u32w(&mut n, 0x1400, 1, 0x0000_0206), Ok(()));
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x8000_0185), Ok(()));
    assert_eq!(u32w(&mut n, 0x1400, 1, 0x0000_0207), Err(0x0609_0030));
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x0000_0186), Ok(()));
    assert_eq!(n.sdo_read(0x1400, 1), Ok(vec![0x06, 0x02, 0, 0]));
    assert_eq!(n.sdo_read(0x1800, 1), Ok(vec![0x86, 0x01, 0, 0]));
}

/// CiA 301 §7.5.2.35: bit 29 set asks for a 29-bit identifier, which this node does not support:
/// 0x06090030, for a valid or an invalid PDO.
#[test]
fn a_29_bit_pdo_cob_id_is_refused() {
    let mut n = node();
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x2000_0185), Err(0x0609_0030));
    assert_eq!(u32w(&mut n, 0x1800, 1, 0xA000_0185), Err(0x0609_0030));
    assert_eq!(u32w(&mut n, 0x1400, 1, 0x2000_0205), Err(0x0609_0030));
    assert_eq!(n.sdo_read(0x1800, 1), Ok(vec![0x85, 0x01, 0, 0]));
}

/// CiA 301 §7.5.2.35: a TPDO's inhibit time (sub-index 3) is changed only while the TPDO is invalid
/// (0x06090030 otherwise); an RPDO's sub-index 3 has no such rule.
#[test]
fn a_tpdo_inhibit_time_changes_only_while_the_tpdo_is_invalid() {
    let mut n = node();
    assert_eq!(n.sdo_write(0x1800, 3, &[100, 0]), Err(0x0609_0030));
    assert_eq!(n.sdo_write(0x1400, 3, &[100, 0]), Ok(()));
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x8000_0185), Ok(()));
    assert_eq!(n.sdo_write(0x1800, 3, &[100, 0]), Ok(()));
    assert_eq!(n.sdo_read(0x1800, 3), Ok(vec![100, 0]));
}

/// CiA 301 §7.5.2.36: a mapping is changed only while its own PDO is invalid (0x06040043 otherwise),
/// and takes only what may be mapped in its direction: the inputs 0x6000 into a TPDO, not into an
/// RPDO (0x06040041).
#[test]
fn a_mapping_changes_only_while_its_own_pdo_is_invalid() {
    let mut n = node();
    assert_eq!(n.sdo_write(0x1600, 0, &[0]), Err(0x0604_0043));
    assert_eq!(n.sdo_write(0x1A00, 0, &[0]), Err(0x0604_0043));
    // RPDO 1 and TPDO 1 invalid; RPDO 2 and TPDO 2 stay valid.
    assert_eq!(u32w(&mut n, 0x1400, 1, 0x8000_0205), Ok(()));
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x8000_0185), Ok(()));
    assert_eq!(n.sdo_write(0x1600, 0, &[0]), Ok(()));
    assert_eq!(n.sdo_write(0x1A00, 0, &[0]), Ok(()));
    assert_eq!(n.sdo_write(0x1601, 0, &[0]), Err(0x0604_0043));
    assert_eq!(n.sdo_write(0x1A01, 0, &[0]), Err(0x0604_0043));
    assert_eq!(u32w(&mut n, 0x1A00, 1, 0x6000_0108), Ok(()));
    assert_eq!(u32w(&mut n, 0x1600, 1, 0x6000_0108), Err(0x0604_0041));
}

/// CiA 301 §7.4.7.1: a dummy entry maps a data-type index 0x0002–0x0007 with sub-index 0 and the
/// type's length (8, 16 or 32 bits); another length or sub-index cannot be mapped (0x06040041), and
/// 0x0020 is no data type of a dummy but an object this dictionary does not have (0x06020000).
#[test]
fn dummy_entries_of_the_mapping() {
    let mut n = node();
    assert_eq!(u32w(&mut n, 0x1400, 1, 0x8000_0205), Ok(()));
    assert_eq!(n.sdo_write(0x1600, 0, &[0]), Ok(()));
    for raw in [
        0x0002_0008u32,
        0x0005_0008,
        0x0003_0010,
        0x0006_0010,
        0x0004_0020,
        0x0007_0020,
    ] {
        assert_eq!(u32w(&mut n, 0x1600, 1, raw), Ok(()), "{raw:#010x}");
    }
    for raw in [0x0005_0010u32, 0x0007_0008, 0x0005_0108] {
        assert_eq!(
            u32w(&mut n, 0x1600, 1, raw),
            Err(0x0604_0041),
            "{raw:#010x}"
        );
    }
    assert_eq!(u32w(&mut n, 0x1600, 1, 0x0020_0008), Err(0x0602_0000));
}

/// With granularity 8 (the description's), a length that is not whole bytes cannot be mapped
/// (0x06040041), whatever the object.
#[test]
fn a_mapping_length_of_part_of_a_byte_is_refused() {
    let mut n = node();
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x8000_0185), Ok(()));
    assert_eq!(n.sdo_write(0x1A00, 0, &[0]), Ok(()));
    assert_eq!(u32w(&mut n, 0x1A00, 1, 0x6000_0104), Err(0x0604_0041));
    assert_eq!(u32w(&mut n, 0x1A00, 1, 0x2F00_0004), Err(0x0604_0041));
    assert_eq!(u32w(&mut n, 0x1A00, 1, 0x2F00_0100), Err(0x0604_0041));
}

/// Dummy entries take room on the wire (CiA 301 §7.4.7.1): an RPDO's dummy bytes are skipped, the
/// entry after them, ending with the frame, is applied; a TPDO's dummy bytes are zero.
#[test]
fn dummy_entries_take_room_on_the_wire() {
    let mut n = node();
    assert_eq!(u32w(&mut n, 0x1400, 1, 0x8000_0205), Ok(()));
    assert_eq!(n.sdo_write(0x1600, 0, &[0]), Ok(()));
    assert_eq!(u32w(&mut n, 0x1600, 1, 0x0007_0020), Ok(()));
    assert_eq!(u32w(&mut n, 0x1600, 2, 0x6411_0110), Ok(()));
    assert_eq!(n.sdo_write(0x1600, 0, &[2]), Ok(()));
    assert_eq!(u32w(&mut n, 0x1400, 1, 0x0000_0205), Ok(()));
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x8000_0185), Ok(()));
    assert_eq!(n.sdo_write(0x1A00, 0, &[0]), Ok(()));
    assert_eq!(u32w(&mut n, 0x1A00, 1, 0x0005_0008), Ok(()));
    assert_eq!(u32w(&mut n, 0x1A00, 2, 0x6000_0208), Ok(()));
    assert_eq!(n.sdo_write(0x1A00, 0, &[2]), Ok(()));
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x0000_0185), Ok(()));
    n.node.app_mut().inputs = [0x11, 0x22];
    assert_eq!(n.nmt(0x01, ID), vec![f(0x185, &[0x00, 0x22])]);
    assert!(n
        .send(f(0x205, &[0xDE, 0xAD, 0xBE, 0xEF, 0x34, 0x12]))
        .is_empty());
    assert_eq!(n.sdo_read(0x6411, 1), Ok(vec![0x34, 0x12]));
    // The default mapping of RPDO 2 is unchanged: nothing else was written.
    assert_eq!(n.sdo_read(0x6411, 2), Ok(vec![0, 0]));
}

/// An RPDO applies every mapped entry, the last one ending with the frame (CiA 301 §7.2.2).
#[test]
fn an_rpdo_applies_every_entry_up_to_its_last_byte() {
    let mut n = node();
    n.nmt(0x01, ID);
    assert!(n.send(f(0x205, &[0x5A, 0xA5])).is_empty());
    assert_eq!(n.sdo_read(0x6200, 1), Ok(vec![0x5A]));
    assert_eq!(n.sdo_read(0x6200, 2), Ok(vec![0xA5]));
}

/// CiA 301 §7.5.2.36 step 4: the number of entries may be at most the entries the object has, each
/// counted one must be valid and not empty (0x06040043), 64 bits in all (exactly 64 is allowed, a
/// whole 8-byte frame; more is 0x06040042).
#[test]
fn the_number_of_mapped_entries_and_their_bits() {
    let mut n = node();
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x8000_0185), Ok(()));
    assert_eq!(n.sdo_write(0x1A00, 0, &[0]), Ok(()));
    // 16 + 16 + 8 + 8 + 16 = 64 bits in 5 of the 8 entries.
    for (sub, raw) in [
        (1u8, 0x6401_0110u32),
        (2, 0x6401_0210),
        (3, 0x6000_0108),
        (4, 0x6000_0208),
        (5, 0x0006_0010),
    ] {
        assert_eq!(u32w(&mut n, 0x1A00, sub, raw), Ok(()));
    }
    assert_eq!(n.sdo_write(0x1A00, 0, &[5]), Ok(()));
    // One more byte: 72 bits.
    assert_eq!(n.sdo_write(0x1A00, 0, &[0]), Ok(()));
    assert_eq!(u32w(&mut n, 0x1A00, 6, 0x0005_0008), Ok(()));
    assert_eq!(n.sdo_write(0x1A00, 0, &[6]), Err(0x0604_0042));
    // An empty entry among the counted ones.
    assert_eq!(u32w(&mut n, 0x1A00, 2, 0), Ok(()));
    assert_eq!(n.sdo_write(0x1A00, 0, &[2]), Err(0x0604_0043));
    assert_eq!(n.sdo_read(0x1A00, 0), Ok(vec![0]));
    // The 64-bit mapping on the wire: 8 bytes, the inputs at bytes 4 and 5.
    assert_eq!(u32w(&mut n, 0x1A00, 2, 0x6401_0210), Ok(()));
    assert_eq!(n.sdo_write(0x1A00, 0, &[5]), Ok(()));
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x0000_0185), Ok(()));
    n.node.app_mut().inputs = [0x11, 0x22];
    assert_eq!(
        n.nmt(0x01, ID),
        vec![f(0x185, &[0, 0, 0, 0, 0x11, 0x22, 0, 0])]
    );
}

/// Only writing 0 to 0x1003:00 clears the error history (CiA 301 §7.5.2.5), and only sub-indices 1
/// and above of 0x1010 and 0x1011 take the "save" and "load" signatures (§7.5.2.13, §7.5.2.14): a
/// description that makes one of their other entries writable gets a plain entry there. (The example
/// description has 0x1003:00 read-only; CiA 301 makes it writable.)
#[test]
fn only_the_command_entries_of_1003_1010_1011_are_commands() {
    let mut dict = io_device();
    for (index, sub) in [(0x1003u16, 0u8), (0x1003, 1), (0x1010, 0), (0x1011, 0)] {
        let entry = dict.object_mut(index).unwrap().subs.get_mut(&sub).unwrap();
        entry.access.kind = AccessType::Rw;
    }
    let mut n = node_of(dict);
    assert_eq!(u32w(&mut n, 0x1003, 1, 0x0000_1234), Ok(()));
    assert_eq!(n.sdo_write(0x1010, 0, &[1]), Ok(()));
    assert_eq!(n.sdo_write(0x1011, 0, &[1]), Ok(()));
    assert_eq!(n.node.poll_storage(), None, "neither saved nor restored");
    // The commands themselves.
    assert_eq!(n.sdo_write(0x1003, 0, &[1]), Err(0x0609_0030));
    assert_eq!(n.sdo_write(0x1003, 0, &[0]), Ok(()));
    assert_eq!(n.sdo_write(0x1010, 1, b"savf"), Err(0x0800_0020));
    assert_eq!(n.sdo_write(0x1011, 1, b"lobd"), Err(0x0800_0020));
}

/// CiA 301 §7.5.2.6/§7.5.2.7: a SYNC producer switched on by 0x1005 bit 30 sends its first SYNC one
/// communication cycle period (0x1006) after the write, not at the write.
#[test]
fn a_sync_producer_starts_one_period_after_it_is_switched_on() {
    let mut n = node();
    assert_eq!(u32w(&mut n, 0x1006, 0, 10_000), Ok(()));
    n.advance_ms(3);
    assert_eq!(u32w(&mut n, 0x1005, 0, 0x4000_0080), Ok(()));
    n.advance_ms(20);
    assert_eq!(
        n.sent_on(0x080),
        vec![(ms(13), f(0x080, &[])), (ms(23), f(0x080, &[]))]
    );
}

/// CiA 301 §7.3.2.2.1: reset communication sets the communication parameters (0x1000–0x1FFF) to their
/// stored values and leaves the application's as they are; reset node loads both.
#[test]
fn reset_communication_loads_only_the_stored_communication_parameters() {
    let mut n = node();
    assert_eq!(n.sdo_write(0x1017, 0, &[100, 0]), Ok(()));
    assert_eq!(n.sdo_write(0x2001, 0, b"AB"), Ok(()));
    assert_eq!(n.sdo_write(0x1010, 1, b"save"), Ok(()));
    assert_eq!(n.sdo_write(0x1017, 0, &[200, 0]), Ok(()));
    assert_eq!(n.sdo_write(0x2001, 0, b"CD"), Ok(()));
    assert_eq!(n.nmt(0x82, ID), vec![f(0x705, &[0x00])]);
    assert_eq!(n.sdo_read(0x1017, 0), Ok(vec![100, 0]));
    assert_eq!(n.sdo_read(0x2001, 0), Ok(b"CD".to_vec()));
    assert_eq!(n.nmt(0x81, ID), vec![f(0x705, &[0x00])]);
    assert_eq!(n.sdo_read(0x1017, 0), Ok(vec![100, 0]));
    assert_eq!(n.sdo_read(0x2001, 0), Ok(b"AB".to_vec()));
}

/// CiA 301 §7.5.2.20: 0x1016:01 monitors the node-ID in bits 16–23 when it is 1–127; node-ID 0 or
/// one above 127 monitors nothing. A monitored heartbeat missing for its time raises EMCY 0x8130
/// (error register 0x11) with the node-ID, and the node leaves Operational.
#[test]
fn the_heartbeat_consumer_monitors_node_ids_1_to_127_only() {
    let mut n = node();
    n.nmt(0x01, ID);
    for raw in [0x0000_0064u32, 0x0080_0064] {
        assert_eq!(u32w(&mut n, 0x1016, 1, raw), Ok(()));
        let producer = 0x700 + (raw >> 16) as u16;
        assert!(n.send(f(producer, &[0x05])).is_empty());
        assert!(n.advance_ms(200).is_empty(), "{raw:#010x}");
        assert_eq!(n.node.state(), NmtState::Operational);
    }
    assert_eq!(u32w(&mut n, 0x1016, 1, 0x0020_0064), Ok(()));
    assert!(n.send(f(0x720, &[0x05])).is_empty());
    n.advance(ms(100) - Duration::from_nanos(1));
    assert_eq!(n.node.state(), NmtState::Operational);
    assert_eq!(
        n.advance(Duration::from_nanos(1)),
        vec![f(0x085, &[0x30, 0x81, 0x11, 0x20, 0, 0, 0, 0])]
    );
    assert_eq!(n.node.state(), NmtState::PreOperational);
}

/// An RPDO shorter than its mapping while an error is active: the EMCY 0x8210's error register keeps
/// the active error's bits and adds generic and communication error (CiA 301 §7.5.2.2: 0x11).
#[test]
fn a_short_rpdo_emcy_keeps_the_active_error_bits() {
    let mut n = node();
    assert_eq!(u32w(&mut n, 0x1016, 1, 0x0020_0064), Ok(()));
    n.nmt(0x01, ID);
    n.send(f(0x720, &[0x05]));
    n.advance_ms(100);
    assert_eq!(n.node.state(), NmtState::PreOperational);
    n.nmt(0x01, ID);
    assert_eq!(
        n.send(f(0x205, &[0x01])),
        vec![f(0x085, &[0x10, 0x82, 0x11, 0x05, 0x02, 1, 2, 0])]
    );
}

/// The PDO configuration the dictionary holds, read back: direction from the index (0x1400+ receive,
/// 0x1800+ transmit), the entries decoded from `index << 16 | sub << 8 | bits`.
#[test]
fn pdo_configurations_read_from_the_dictionary() {
    let mut n = node();
    let rpdo = PdoConfig::read(n.node.dict(), 0x1400).unwrap();
    assert_eq!(
        rpdo,
        PdoConfig {
            dir: Direction::Rx,
            comm: 0x1400,
            cob_raw: 0x205,
            transmission: 255,
            inhibit: 0,
            event_timer: 0,
            map: vec![
                MapEntry {
                    index: 0x6200,
                    sub: 1,
                    bits: 8
                },
                MapEntry {
                    index: 0x6200,
                    sub: 2,
                    bits: 8
                },
            ],
        }
    );
    assert!(!rpdo.is_empty());
    let tpdo = PdoConfig::read(n.node.dict(), 0x1801).unwrap();
    assert_eq!(
        (tpdo.dir, tpdo.cob_raw, tpdo.len()),
        (Direction::Tx, 0x285, 4)
    );
    assert_eq!(
        PdoConfig::read(n.node.dict(), 0x1800).unwrap().dir,
        Direction::Tx
    );
    assert_eq!(PdoConfig::read(n.node.dict(), 0x1402), None);
    assert_eq!(u32w(&mut n, 0x1400, 1, 0x8000_0205), Ok(()));
    assert_eq!(n.sdo_write(0x1600, 0, &[0]), Ok(()));
    let empty = PdoConfig::read(n.node.dict(), 0x1400).unwrap();
    assert!(empty.is_empty() && !empty.valid());
    let e = MapEntry::from_raw(0x6401_0210);
    assert_eq!(
        e,
        MapEntry {
            index: 0x6401,
            sub: 2,
            bits: 16
        }
    );
    assert_eq!((e.len(), e.is_empty(), e.is_dummy()), (2, false, false));
    assert!(MapEntry::from_raw(0x6000_0100).is_empty());
    assert!(MapEntry::from_raw(0x0007_0020).is_dummy());
}

/// Entering Operational, every event-driven TPDO (254/255) is sent once (CiA 301 §7.2.2.2), also one
/// made event-driven in Pre-operational: TPDO 2 (type 1 in the description) set to 255.
#[test]
fn a_tpdo_made_event_driven_in_pre_operational_is_sent_on_entering_operational() {
    let mut n = node();
    assert_eq!(n.sdo_write(0x1801, 2, &[255]), Ok(()));
    n.node.app_mut().inputs = [0x12, 0x34];
    assert_eq!(
        n.nmt(0x01, ID),
        vec![f(0x185, &[0x12, 0x34]), f(0x285, &[0, 0, 0, 0])]
    );
}

/// A PDO parameter written in Operational starts only a TPDO that has just become valid afresh: an
/// event-driven one is sent at once (with the download's confirmation); the TPDOs that stay valid are
/// not sent again.
#[test]
fn a_tpdo_that_becomes_valid_in_operational_is_sent_at_once() {
    let mut n = node();
    n.node.app_mut().inputs = [0x12, 0x34];
    assert_eq!(n.nmt(0x01, ID), vec![f(0x185, &[0x12, 0x34])]);
    assert_eq!(
        download(&mut n, 0x1400, 3, &[0, 0]),
        vec![confirmed(0x1400, 3)]
    );
    assert_eq!(
        download(&mut n, 0x1801, 1, &0x8000_0285u32.to_le_bytes()),
        vec![confirmed(0x1801, 1)]
    );
    assert_eq!(
        download(&mut n, 0x1800, 1, &0x8000_0185u32.to_le_bytes()),
        vec![confirmed(0x1800, 1)]
    );
    assert_eq!(
        download(&mut n, 0x1800, 1, &0x0000_0185u32.to_le_bytes()),
        vec![confirmed(0x1800, 1), f(0x185, &[0x12, 0x34])]
    );
}

/// CiA 301 §7.5.2.35: the event timer (sub-index 5, ms) of an event-driven TPDO sends it when it was
/// not sent for that time: type 254 with 100 ms sends at the start and then every 100 ms.
#[test]
fn the_event_timer_sends_an_unchanged_tpdo_every_period() {
    let mut n = node();
    assert_eq!(n.sdo_write(0x1800, 2, &[254]), Ok(()));
    assert_eq!(n.sdo_write(0x1800, 5, &[100, 0]), Ok(()));
    n.advance_ms(7);
    n.node.app_mut().inputs = [0x12, 0x34];
    assert_eq!(n.nmt(0x01, ID), vec![f(0x185, &[0x12, 0x34])]);
    n.advance_ms(300);
    let times: Vec<Duration> = n.sent_on(0x185).into_iter().map(|(t, _)| t).collect();
    assert_eq!(times, [ms(7), ms(107), ms(207), ms(307)]);
}

/// CiA 301 §7.5.2.35: the event timer is for event-driven TPDOs (254/255) only; a synchronous TPDO
/// with one set is sent on SYNC alone, and the node asks for no timer for it.
#[test]
fn the_event_timer_of_a_synchronous_tpdo_does_nothing() {
    let mut n = node();
    assert_eq!(n.sdo_write(0x1801, 5, &[100, 0]), Ok(()));
    assert_eq!(
        n.sdo_write(0x1800, 1, &0x8000_0185u32.to_le_bytes()),
        Ok(())
    );
    n.nmt(0x01, ID);
    assert_eq!(sync(&mut n), vec![f(0x285, &[0, 0, 0, 0])]);
    assert_eq!(n.node.poll_timeout(), None);
}

/// CiA 301 §7.5.2.35: the inhibit time (sub-index 3, 100 µs) is the least time between two
/// transmissions of a TPDO; a change within it is sent when it ends, and the node asks to be woken
/// exactly then.
#[test]
fn a_change_within_the_inhibit_time_is_sent_when_it_ends() {
    let mut n = node();
    assert_eq!(
        n.sdo_write(0x1800, 1, &0x8000_0185u32.to_le_bytes()),
        Ok(())
    );
    // 100 × 100 µs = 10 ms.
    assert_eq!(n.sdo_write(0x1800, 3, &[100, 0]), Ok(()));
    assert_eq!(
        n.sdo_write(0x1800, 1, &0x0000_0185u32.to_le_bytes()),
        Ok(())
    );
    let start = n.now;
    assert_eq!(n.nmt(0x01, ID), vec![f(0x185, &[0, 0])]);
    n.advance_ms(3);
    assert!(inputs(&mut n, [1, 0]).is_empty());
    assert_eq!(n.node.poll_timeout(), Some(start + ms(10)));
    assert!(n.advance(ms(7) - Duration::from_nanos(1)).is_empty());
    assert_eq!(n.stall(Duration::from_nanos(1)), vec![f(0x185, &[1, 0])]);
    assert_eq!(n.node.poll_timeout(), None);
    // Past the inhibit time: at once.
    n.advance_ms(15);
    assert_eq!(inputs(&mut n, [2, 0]), vec![f(0x185, &[2, 0])]);
}

/// CiA 301 §7.2.2.2, type 0 (acyclic synchronous): the TPDO is sent at the SYNC after an event, the
/// device's report of changed data, even one changed back since; not at the event, and not at a
/// SYNC without one. The first SYNC in Operational sends it (nothing was sent before).
#[test]
fn an_acyclic_synchronous_tpdo_is_sent_at_the_sync_after_a_change() {
    let mut n = node();
    assert_eq!(n.sdo_write(0x1800, 2, &[0]), Ok(()));
    assert!(n.nmt(0x01, ID).is_empty());
    let tpdo2 = f(0x285, &[0, 0, 0, 0]);
    assert_eq!(sync(&mut n), vec![f(0x185, &[0, 0]), tpdo2]);
    assert_eq!(sync(&mut n), vec![tpdo2]);
    assert!(inputs(&mut n, [1, 0]).is_empty());
    assert!(inputs(&mut n, [0, 0]).is_empty());
    assert_eq!(sync(&mut n), vec![f(0x185, &[0, 0]), tpdo2]);
    assert!(inputs(&mut n, [2, 0]).is_empty());
    assert_eq!(sync(&mut n), vec![f(0x185, &[2, 0]), tpdo2]);
    assert_eq!(sync(&mut n), vec![tpdo2]);
}

/// CiA 301 §7.2.2.2 and §7.5.2.35 bit 30: a remote frame on a TPDO's CAN-ID asks for its current data
/// in Operational, unless bit 30 forbids remote requests; a remote frame on another CAN-ID is none.
#[test]
fn a_remote_frame_asks_for_a_tpdo_unless_bit_30_forbids_it() {
    let rtr = |id: u16| CanFrame::new_remote_frame(u32::from(id), false, 0).unwrap();
    let mut n = node();
    assert_eq!(
        n.sdo_write(0x1801, 1, &0x4000_0285u32.to_le_bytes()),
        Ok(())
    );
    assert!(n.send(rtr(0x185)).is_empty(), "Pre-operational");
    n.nmt(0x01, ID);
    n.node.app_mut().inputs = [7, 8];
    assert_eq!(n.send(rtr(0x185)), vec![f(0x185, &[7, 8])]);
    assert!(n.send(rtr(0x285)).is_empty());
    assert!(n.send(rtr(0x385)).is_empty());
}

/// CiA 301 §7.2.2.2, types 252 and 253: sent on a remote frame only, never on a SYNC or a change;
/// type 252 answers with the data sampled at the last SYNC (the current data before the first), 253
/// with the data of the moment.
#[test]
fn remote_request_only_tpdos_answer_with_the_sampled_or_the_current_data() {
    let rtr = |id: u16| CanFrame::new_remote_frame(u32::from(id), false, 0).unwrap();
    let mut n = node();
    assert_eq!(n.sdo_write(0x1800, 2, &[252]), Ok(()));
    // TPDO 2 is sent on SYNC only as the description has it: invalid here, to keep the SYNCs quiet.
    assert_eq!(
        n.sdo_write(0x1801, 1, &0x8000_0285u32.to_le_bytes()),
        Ok(())
    );
    assert!(n.nmt(0x01, ID).is_empty());
    assert!(inputs(&mut n, [3, 4]).is_empty());
    // Before any SYNC: the current data.
    assert_eq!(n.send(rtr(0x185)), vec![f(0x185, &[3, 4])]);
    assert!(sync(&mut n).is_empty());
    assert!(inputs(&mut n, [5, 6]).is_empty());
    assert!(n.advance_ms(100).is_empty());
    // What the SYNC sampled, [3, 4], not the moment's [5, 6].
    assert_eq!(n.send(rtr(0x185)), vec![f(0x185, &[3, 4])]);
    assert!(sync(&mut n).is_empty());
    assert_eq!(n.send(rtr(0x185)), vec![f(0x185, &[5, 6])]);
    // Type 253: the moment's data, nothing on a SYNC or a change.
    assert_eq!(n.sdo_write(0x1800, 2, &[253]), Ok(()));
    assert!(inputs(&mut n, [7, 8]).is_empty());
    assert!(sync(&mut n).is_empty());
    assert!(inputs(&mut n, [9, 10]).is_empty());
    assert_eq!(n.send(rtr(0x185)), vec![f(0x185, &[9, 10])]);
}

/// The device runs at a SYNC up to it and may change there (a drive's control ticks up to the SYNC:
/// a quick stop that ends in Switch on disabled), then asks for no timeout at which the node would
/// see the change: the node checks its event-driven TPDOs after the SYNC all the same, asking for
/// its timers at once, and sends the change then. So when the SYNC comes exactly at the instant the
/// device's timeout falls due (the device runs it inside the SYNC) and when it comes later, before
/// the node's own timer ran (a host that takes a frame before an overdue timer: the node runs the
/// device up to the SYNC).
#[test]
fn a_change_the_device_makes_up_to_a_sync_is_sent_by_an_event_driven_tpdo() {
    let mut n = node();
    assert_eq!(n.nmt(0x01, ID), vec![f(0x185, &[0, 0])]);
    let tpdo2 = f(0x285, &[0, 0, 0, 0]);
    for (k, late) in [(1u8, Duration::ZERO), (2, Duration::from_micros(300))] {
        let at = n.now + ms(1);
        let app = n.node.app_mut();
        app.next = Some([k, 0]);
        app.due = Some(at);
        n.now = at + late;
        n.node.handle_frame(n.now, &f(0x080, &[]));
        assert_eq!(n.node.poll_timeout(), Some(n.now), "late by {late:?}");
        assert_eq!(
            n.stall(Duration::ZERO),
            vec![tpdo2, f(0x185, &[k, 0])],
            "late by {late:?}"
        );
        assert_eq!(n.node.poll_timeout(), None);
    }
}

/// Within one instant the node works in the order its timers are documented: the device's report
/// first, its changed TPDO on the wire before the heartbeat due at the same instant.
#[test]
fn a_changed_tpdo_goes_out_before_a_heartbeat_due_at_the_same_instant() {
    let mut n = node();
    assert_eq!(n.sdo_write(0x1017, 0, &[10, 0]), Ok(()));
    assert_eq!(n.nmt(0x01, ID), vec![f(0x185, &[0, 0])]);
    let at = n.now + ms(10);
    let app = n.node.app_mut();
    app.inputs = [1, 0];
    app.due = Some(at);
    assert_eq!(n.advance_ms(10), vec![f(0x185, &[1, 0]), f(0x705, &[0x05])]);
}

/// A value the node reports is taken back written as read, whatever the rules say, since it changes
/// nothing (`sdo-tool dump`, then `apply`): a mapping entry and the count of a valid PDO (which the
/// procedure would refuse, 0x06040043), a valid TPDO's inhibit time, its COB-ID, the EMCY COB-ID;
/// another value is refused as before.
#[test]
fn a_value_the_node_holds_is_taken_back_unchanged() {
    let mut n = node();
    // TPDO 1 valid on 0x185, mapping 0x6000:01 and 0x6000:02 (8 bits each).
    assert_eq!(u32w(&mut n, 0x1A00, 1, 0x6000_0108), Ok(()));
    assert_eq!(n.sdo_write(0x1A00, 0, &[2]), Ok(()));
    assert_eq!(u32w(&mut n, 0x1A00, 1, 0x6000_0208), Err(0x0604_0043));
    assert_eq!(n.sdo_write(0x1A00, 0, &[1]), Err(0x0604_0043));
    assert_eq!(n.sdo_write(0x1800, 3, &[0, 0]), Ok(()));
    assert_eq!(n.sdo_write(0x1800, 3, &[100, 0]), Err(0x0609_0030));
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x0000_0185), Ok(()));
    assert_eq!(u32w(&mut n, 0x1800, 1, 0x0000_0186), Err(0x0609_0030));
    assert_eq!(u32w(&mut n, 0x1014, 0, 0x0000_0085), Ok(()));
    assert_eq!(n.sdo_read(0x1A00, 1), Ok(vec![0x08, 0x01, 0x00, 0x60]));
    assert_eq!(n.sdo_read(0x1800, 3), Ok(vec![0, 0]));
}
