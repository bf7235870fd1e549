//! ethercrab (the Rust EtherCAT master) against two virtual SMD23K-B on a veth pair: it finds and
//! identifies them from their SII, reads and writes their CoE dictionary in Pre-Op (a string
//! upload, an expedited download read back, refused transfers with their abort codes), brings them to
//! Op in one process-data group and drives a Relative move on each with a 1 ms cycle until
//! Move_Complete, with the motor position exactly at the target; then a second master run finds
//! them again and reads their dictionary.
//!
//! 0x1008 (8 bytes) comes as a normal upload: more than an expedited one holds, and all of it fits
//! the 128-byte mailbox, so the unit sends no segments.
//!
//! The master's TX/RX task (ethercrab's Linux raw socket) and the test run in one executor
//! (`async_io::block_on`, the one smol's `block_on` is), joined with `futures_lite::future::or`: when
//! the test's future ends, the TX/RX task is dropped with it.

use testkit::link;

use std::time::{Duration, Instant};

use ethercrab::error::{CoeAbortCode, Error, MailboxError};
use ethercrab::std::{ethercat_now, tx_rx_task};
use ethercrab::{
    MainDevice, MainDeviceConfig, PduStorage, RetryBehaviour, SubDevice, SubDeviceRef, Timeouts,
};
use futures_lite::{future, StreamExt};

/// SubDevices a group holds at most (a power of two).
const MAX_SUBDEVICES: usize = 8;
/// The group's process data image: 2 × (20 output + 20 input bytes), with room.
const MAX_PDI: usize = 128;
/// Frames in flight at most, and the data one PDU carries at most (a 128-byte mailbox fits).
const MAX_FRAMES: usize = 16;
const MAX_PDU_DATA: usize = PduStorage::element_size(1100);

static PDU_STORAGE: PduStorage<MAX_FRAMES, MAX_PDU_DATA> = PduStorage::new();

/// STATUS_word0 bit 7.
const MOVE_COMPLETE: u16 = 1 << 7;
/// STATUS_word1 bit 5: the unit is in Pre-Op or Safe-Op.
const PREOP_SAFEOP: u16 = 1 << 5;
/// CMD_word0 bit 9 (Preset Position) and bit 1 (Relative Move).
const PRESET_POSITION: u16 = 1 << 9;
const RELATIVE_MOVE: u16 = 1 << 1;

/// The 20 output bytes (0x7000:01–08, little-endian).
#[derive(Debug, Clone, Copy, Default)]
struct Outputs {
    cmd0: u16,
    cmd1: u16,
    position: i32,
    velocity: u32,
    acceleration: u16,
    deceleration: u16,
    motor_current: u16,
    jerk: u16,
}

impl Outputs {
    fn write_to(&self, b: &mut [u8]) {
        assert_eq!(b.len(), 20, "20 output bytes per unit");
        b[0..2].copy_from_slice(&self.cmd0.to_le_bytes());
        b[2..4].copy_from_slice(&self.cmd1.to_le_bytes());
        b[4..8].copy_from_slice(&self.position.to_le_bytes());
        b[8..12].copy_from_slice(&self.velocity.to_le_bytes());
        b[12..14].copy_from_slice(&self.acceleration.to_le_bytes());
        b[14..16].copy_from_slice(&self.deceleration.to_le_bytes());
        b[16..18].copy_from_slice(&self.motor_current.to_le_bytes());
        b[18..20].copy_from_slice(&self.jerk.to_le_bytes());
    }
}

/// The 20 input bytes (0x6000:01–07, little-endian).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Inputs {
    status0: u16,
    status1: u16,
    motor_position: i32,
    encoder_position: i32,
    trapped_encoder_position: i32,
    motor_current: u16,
    jerk: u16,
}

impl Inputs {
    fn read(b: &[u8]) -> Inputs {
        assert_eq!(b.len(), 20, "20 input bytes per unit");
        let u16_at = |o: usize| u16::from_le_bytes([b[o], b[o + 1]]);
        let i32_at = |o: usize| i32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
        Inputs {
            status0: u16_at(0),
            status1: u16_at(2),
            motor_position: i32_at(4),
            encoder_position: i32_at(8),
            trapped_encoder_position: i32_at(12),
            motor_current: u16_at(16),
            jerk: u16_at(18),
        }
    }
}

/// The abort code of an SDO transfer the SubDevice refused.
fn abort_code(e: &Error) -> Option<u32> {
    match e {
        Error::Mailbox(MailboxError::Aborted { code, .. }) => Some(u32::from(*code)),
        _ => None,
    }
}

/// ethercrab's timeouts, generous for a loaded machine: a frame that comes back after its PDU
/// timeout ends ethercrab's TX/RX task (ReceiveFrame), and the emulator is a process of its own.
fn timeouts_for_a_loaded_machine() -> Timeouts {
    Timeouts {
        pdu: Duration::from_millis(1000),
        eeprom: Duration::from_millis(1000),
        wait_loop_delay: Duration::from_millis(1),
        mailbox_response: Duration::from_millis(1000),
        ..Timeouts::default()
    }
}

/// Pre-Op: CoE through the mailbox of both units (a string upload, an expedited download read
/// back, refused transfers with their abort codes).
async fn coe_in_pre_op(unit1: &SubDeviceRef<'_, &SubDevice>, unit2: &SubDeviceRef<'_, &SubDevice>) {
    let name: [u8; 8] = unit1.sdo_read(0x1008, 0).await.expect("0x1008");
    assert_eq!(&name, b"SMD23K-B");
    let serial: u32 = unit2.sdo_read(0x1018, 4).await.expect("0x1018:04");
    assert_eq!(serial, 2);
    // Starting_Speed (0x8010:03, UDINT rw, 1 to 1,999,999 steps/s): default 141.
    let speed: u32 = unit1.sdo_read(0x8010, 3).await.expect("0x8010:03");
    assert_eq!(speed, 141);
    unit1.sdo_write(0x8010, 3, 500u32).await.expect("write");
    let speed: u32 = unit1.sdo_read(0x8010, 3).await.expect("read back");
    assert_eq!(speed, 500);
    let other: u32 = unit2.sdo_read(0x8010, 3).await.unwrap();
    assert_eq!(other, 141, "unit 2 untouched");
    unit1.sdo_write(0x8010, 3, 141u32).await.expect("restore");
    // Refused: the identity is read-only; a UINT into the UDINT is too short.
    let e = unit1.sdo_write(0x1018, 4, 7u32).await.unwrap_err();
    assert_eq!(abort_code(&e), Some(0x0601_0002), "{e}");
    let e = unit1.sdo_write(0x8010, 3, 7u16).await.unwrap_err();
    assert_eq!(abort_code(&e), Some(0x0607_0013), "{e}");
    assert!(matches!(
        e,
        Error::Mailbox(MailboxError::Aborted {
            code: CoeAbortCode::DataTooShort,
            address: 0x8010,
            sub_index: 3
        })
    ));
    let e = unit1.sdo_read::<u32>(0x2345, 0).await.unwrap_err();
    assert_eq!(abort_code(&e), Some(0x0602_0000), "{e}");
}

/// A second master run on the same units, as a new process would be: Init again, its mailbox
/// counter from 1 again (the units restart their mailbox in Init).
fn second_master_run(link: &link::Link) {
    let storage: &'static PduStorage<MAX_FRAMES, MAX_PDU_DATA> =
        Box::leak(Box::new(PduStorage::new()));
    let (tx, rx, pdu_loop) = storage.try_split().expect("split once");
    let maindevice = MainDevice::new(
        pdu_loop,
        Timeouts::default(),
        MainDeviceConfig {
            dc_static_sync_iterations: 0,
            ..MainDeviceConfig::default()
        },
    );
    let tx_rx = tx_rx_task(&link.master, tx, rx).expect("open the master's interface");
    let again = async {
        let group = maindevice
            .init_single_group::<MAX_SUBDEVICES, MAX_PDI>(ethercat_now)
            .await
            .expect("init to Pre-Op again");
        let unit2 = group.subdevice(&maindevice, 1).unwrap();
        let serial: u32 = unit2.sdo_read(0x1018, 4).await.expect("0x1018:04");
        assert_eq!(
            serial, 2,
            "the answer to this request, not the last one before"
        );
        let speed: u32 = unit2.sdo_read(0x8010, 3).await.expect("0x8010:03");
        assert_eq!(speed, 141);
    };
    async_io::block_on(future::or(again, async {
        let r = tx_rx.await;
        panic!("the TX/RX task ended: {:?}", r.err());
    }));
}

#[test]
fn ethercrab_finds_configures_and_moves_two_units() {
    let started = Instant::now();
    let link = link::Link::up(&["--units", "2"]);
    let (tx, rx, pdu_loop) = PDU_STORAGE.try_split().expect("split once");
    let maindevice = MainDevice::new(
        pdu_loop,
        timeouts_for_a_loaded_machine(),
        MainDeviceConfig {
            dc_static_sync_iterations: 0,
            retry_behaviour: RetryBehaviour::Count(3),
        },
    );
    let tx_rx = tx_rx_task(&link.master, tx, rx).expect("open the master's interface");
    let tx_rx = async {
        let r = tx_rx.await;
        panic!("the TX/RX task ended: {:?}", r.err());
    };
    let scenario = async {
        let group = maindevice
            .init_single_group::<MAX_SUBDEVICES, MAX_PDI>(ethercat_now)
            .await
            .expect("init to Pre-Op");
        assert_eq!(group.len(), 2, "two SubDevices found");
        for (k, sd) in group.iter(&maindevice).enumerate() {
            assert_eq!(sd.name(), "SMD23K-B", "the name from the SII");
            let id = sd.identity();
            assert_eq!(
                (id.vendor_id, id.product_id, id.revision, id.serial),
                (0x0AC1, 0x2301, 1, k as u32 + 1),
                "identity of unit {}",
                k + 1
            );
        }
        let init_time = started.elapsed();

        // Pre-Op: CoE through the mailbox.
        let unit1 = group.subdevice(&maindevice, 0).unwrap();
        let unit2 = group.subdevice(&maindevice, 1).unwrap();
        coe_in_pre_op(&unit1, &unit2).await;

        // Safe-Op, then Op with the process data running.
        let group = group.into_safe_op(&maindevice).await.expect("Safe-Op");
        let group = group
            .request_into_op(&maindevice)
            .await
            .expect("request Op");
        let mut tick = async_io::Timer::interval(Duration::from_millis(1));
        let mut outputs = [Outputs {
            cmd1: 0x8000,
            velocity: 10_000,
            acceleration: 100,
            deceleration: 100,
            ..Outputs::default()
        }; 2];
        // One cycle: the outputs into the PDI, one LRW, the inputs out of it.
        macro_rules! cycle {
            ($outputs:expr) => {{
                for (k, sd) in group.iter(&maindevice).enumerate() {
                    $outputs[k].write_to(&mut sd.outputs_raw_mut());
                }
                let r = group.tx_rx(&maindevice).await.expect("tx_rx");
                let inputs: Vec<Inputs> = group
                    .iter(&maindevice)
                    .map(|sd| Inputs::read(&sd.inputs_raw()))
                    .collect();
                (r.working_counter, r.all_op(), [inputs[0], inputs[1]])
            }};
        }
        let deadline = Instant::now() + Duration::from_secs(5);
        loop {
            let (_, op, _) = cycle!(outputs);
            if op {
                break;
            }
            assert!(Instant::now() < deadline, "both units in Op");
            tick.next().await;
        }
        let (wkc, _, _) = cycle!(outputs);
        assert_eq!(wkc, 6, "per unit: the LRW's read 1 + write 2");
        // Preset Position to 0 for a few cycles, then 0, then the Relative moves.
        for cmd0 in [PRESET_POSITION, 0] {
            for o in &mut outputs {
                o.cmd0 = cmd0;
                o.position = 0;
            }
            for _ in 0..5 {
                cycle!(outputs);
                tick.next().await;
            }
        }
        // The units' cycle has run in Op since: their inputs say so.
        let (_, _, inputs) = cycle!(outputs);
        for i in &inputs {
            assert_eq!(i.status1 & PREOP_SAFEOP, 0, "in Op: {i:?}");
            assert_eq!(i.motor_position, 0, "preset to 0: {i:?}");
        }
        outputs[0].cmd0 = RELATIVE_MOVE;
        outputs[0].position = 5_000;
        outputs[1].cmd0 = RELATIVE_MOVE;
        outputs[1].position = -2_000;
        let move_started = Instant::now();
        let deadline = move_started + Duration::from_secs(10);
        let last = loop {
            let (wkc, op, inputs) = cycle!(outputs);
            assert_eq!(wkc, 6);
            assert!(op, "still in Op");
            if inputs.iter().all(|i| i.status0 & MOVE_COMPLETE != 0) {
                break inputs;
            }
            assert!(
                Instant::now() < deadline,
                "Move_Complete on both within 10 s: {inputs:?}"
            );
            tick.next().await;
        };
        let move_time = move_started.elapsed();
        assert_eq!(last[0].motor_position, 5_000, "{:?}", last[0]);
        assert_eq!(last[1].motor_position, -2_000, "{:?}", last[1]);
        for i in &last {
            assert_eq!(i.status1 & PREOP_SAFEOP, 0, "in Op: {i:?}");
        }
        let group = group.into_safe_op(&maindevice).await.expect("Op → Safe-Op");
        let group = group.into_pre_op(&maindevice).await.expect("→ Pre-Op");
        group.into_init(&maindevice).await.expect("→ Init");
        (init_time, move_time)
    };
    let (init_time, move_time) = async_io::block_on(future::or(scenario, tx_rx));

    second_master_run(&link);
    eprintln!(
        "ethercrab: init to Pre-Op {init_time:?}, move {move_time:?}, all {:?}",
        started.elapsed()
    );
    drop(link);
}
