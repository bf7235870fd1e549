//! ethercrab (the Rust EtherCAT master) against `ethercat-node` on a veth pair: three vendors'
//! CiA 402 drives from the corpus beside the checkout (Elmo, Ingenia, Copley with two axes) and the
//! example drive, found by their SII, their modes set by SDO where their PDOs lack 0x6060, their
//! process data mapped as ethercrab reads their PDO assignment by SDO, Distributed Clocks with SYNC0
//! every 1 ms, Safe-Op, Op; every axis enabled by its controlword through Shutdown, Switch on and
//! Enable operation, moved in csp along a ramp of one set-point per DC cycle, and 0x6064 read back
//! from the process data and by SDO: exactly each target.
//!
//! The master's TX/RX task (ethercrab's Linux raw socket) and the test run in one executor
//! (`async_io::block_on`), joined with `futures_lite::future::or`.

use testkit::link;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use ethercrab::std::{ethercat_now, tx_rx_task};
use ethercrab::subdevice_group::DcConfiguration;
use ethercrab::{
    DcSync, MainDevice, MainDeviceConfig, PduStorage, RetryBehaviour, SubDevice, SubDeviceRef,
    Timeouts,
};
use futures_lite::future;

const MAX_SUBDEVICES: usize = 8;
const MAX_PDI: usize = 256;
const MAX_FRAMES: usize = 16;
const MAX_PDU_DATA: usize = PduStorage::element_size(1100);

static PDU_STORAGE: PduStorage<MAX_FRAMES, MAX_PDU_DATA> = PduStorage::new();

fn corpus(name: &str) -> String {
    let rel = format!("../shared/corpus/esi/{name}");
    let path = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(&rel);
    assert!(
        path.is_file(),
        "{} is missing: the tests read the vendors' ESIs from the corpus beside the checkout",
        path.display()
    );
    rel
}

/// One drive axis: its unit, number, and where its objects are in the unit's process data (from
/// each ESI's default PDOs, by hand), and whether its mode is set by SDO.
#[derive(Debug, Clone, Copy)]
struct Axis {
    unit: usize,
    number: u16,
    mode_by_sdo: bool,
    mode_at: Option<usize>,
    controlword: usize,
    target: usize,
    statusword: usize,
    position: usize,
}

fn i32_at(b: &[u8], at: usize) -> i32 {
    i32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

/// `ethercat-node` on a fresh veth pair with the three vendors' drives (Elmo, Ingenia, Copley with
/// two axes) and the example drive.
fn start_link() -> link::Link {
    let (elmo, ingenia, copley) = (
        corpus("elmo-ECAT_00010420_V11.xml"),
        corpus("ingenia-eve-xcr-e.xml"),
        corpus("copley-XE2_4.60.xml"),
    );
    link::Link::node(&[
        "--esi",
        &elmo,
        "--device",
        "0x00030924",
        "--esi",
        &ingenia,
        "--esi",
        &copley,
        "--esi",
        "examples/drive.esi.xml",
    ])
}

/// The five drive axes of the four units.
fn axes() -> [Axis; 5] {
    let axis =
        |unit, number, mode_by_sdo, mode_at, controlword, target, statusword, position| Axis {
            unit,
            number,
            mode_by_sdo,
            mode_at,
            controlword,
            target,
            statusword,
            position,
        };
    // Elmo RxPDO 0x1600: 0x607A @0, 0x60FE:01 @4, 0x6040 @8; TxPDO 0x1A00: 0x6064 @0, 0x60FD @4,
    // 0x6041 @8. Ingenia 0x1600: 0x6040 @0, 0x607A @2, 0x60FF @6, 0x6060 @10; 0x1A00: 0x6041 @0,
    // 0x6064 @2. Copley's two csp modules: 0x6040 @0, 0x607A @2 (axis B 12 bytes on); 0x6041 @0,
    // 0x6064 @2 (axis B 16 bytes on). The example drive: 0x6040 @0, 0x607A @2, 0x6060 @6; 0x6041
    // @0, 0x6064 @2.
    [
        axis(0, 0, true, None, 8, 0, 8, 0),
        axis(1, 0, false, Some(10), 0, 2, 0, 2),
        axis(2, 0, true, None, 0, 2, 0, 2),
        axis(2, 1, true, None, 12, 14, 16, 18),
        axis(3, 0, false, Some(6), 0, 2, 0, 2),
    ]
}

/// ethercrab's timeouts, generous for a loaded machine, and 10 s for a state transition.
fn timeouts() -> Timeouts {
    Timeouts {
        pdu: Duration::from_millis(1000),
        eeprom: Duration::from_millis(1000),
        wait_loop_delay: Duration::from_millis(1),
        mailbox_response: Duration::from_millis(1000),
        state_transition: Duration::from_secs(10),
        ..Timeouts::default()
    }
}

/// The units' names, vendor IDs and product codes, in the chain's order.
const EXPECTED: [(&str, u32, u32); 4] = [
    ("Elmo Drive", 0x9A, 0x0003_0924),
    ("EVE-XCR-E", 0x29C, 0x02C3_1001),
    ("XE2", 0xAB, 0x10B0),
    ("drive", 0xABC, 0x402),
];

/// Unit `k` in Pre-Op: its name and identity as [`EXPECTED`], the mode of its axes that have no
/// 0x6060 in their PDOs set to csp by SDO, SYNC0, and the SyncManager watchdog at 1 s.
async fn prepare(sd: &mut SubDeviceRef<'_, &mut SubDevice>, k: usize, axes: &[Axis]) {
    let (name, vendor, product) = EXPECTED[k];
    assert_eq!(sd.name(), name);
    let id = sd.identity();
    assert_eq!(
        (id.vendor_id, id.product_id, id.serial),
        (vendor, product, k as u32 + 1),
        "identity of unit {k}"
    );
    for a in axes.iter().filter(|a| a.unit == k && a.mode_by_sdo) {
        let base = 0x6000 + 0x800 * a.number;
        sd.sdo_write(base + 0x60, 0, 8i8).await.expect("0x6060");
        let mode: i8 = sd.sdo_read(base + 0x60, 0).await.expect("0x6060 back");
        assert_eq!(mode, 8);
    }
    sd.set_dc_sync(DcSync::Sync0);
    // The SyncManager watchdog at 1 s (0x0420 in units of 100 µs at the default divider;
    // the ESI's is 100 ms): the test's master may pause on a machine busy with other jobs.
    sd.register_write(0x0420u16, 10_000u16)
        .await
        .expect("watchdog time 0x0420");
}

#[test]
fn ethercrab_moves_three_vendors_drives_and_the_example_in_csp_with_dc() {
    let started = Instant::now();
    let link = start_link();
    let axes = axes();
    let (tx, rx, pdu_loop) = PDU_STORAGE.try_split().expect("split once");
    let maindevice = MainDevice::new(
        pdu_loop,
        timeouts(),
        MainDeviceConfig {
            dc_static_sync_iterations: 1000,
            retry_behaviour: RetryBehaviour::Count(3),
        },
    );
    let tx_rx = tx_rx_task(&link.master, tx, rx).expect("open the master's interface");
    let tx_rx = async {
        let r = tx_rx.await;
        panic!("the TX/RX task ended: {:?}", r.err());
    };
    let scenario = async {
        let mut group = maindevice
            .init_single_group::<MAX_SUBDEVICES, MAX_PDI>(ethercat_now)
            .await
            .expect("init to Pre-Op");
        assert_eq!(group.len(), 4, "four SubDevices found");
        for (k, mut sd) in group.iter_mut(&maindevice).enumerate() {
            prepare(&mut sd, k, &axes).await;
        }
        let group = group.into_pre_op_pdi(&maindevice).await.expect("PDI");
        let group = group
            .configure_dc_sync(
                &maindevice,
                DcConfiguration {
                    start_delay: Duration::from_millis(50),
                    sync0_period: Duration::from_millis(1),
                    sync0_shift: Duration::ZERO,
                },
            )
            .await
            .expect("DC");
        let group = group.into_safe_op(&maindevice).await.expect("Safe-Op");
        let group = group.request_into_op(&maindevice).await.expect("Op");
        let expected_wkc = 3 * 4;
        // One DC cycle: the outputs into the PDI, one frame, then wait for the next cycle.
        let mut cw = [0u16; 5];
        let mut targets = [0i32; 5];
        macro_rules! cycle {
            () => {{
                for (n, a) in axes.iter().enumerate() {
                    let sd = group.subdevice(&maindevice, a.unit).unwrap();
                    let mut out = sd.outputs_raw_mut();
                    out[a.controlword..a.controlword + 2].copy_from_slice(&cw[n].to_le_bytes());
                    out[a.target..a.target + 4].copy_from_slice(&targets[n].to_le_bytes());
                    if let Some(at) = a.mode_at {
                        out[at] = 8;
                    }
                }
                let now = Instant::now();
                let r = group.tx_rx_dc(&maindevice).await.expect("tx_rx_dc");
                let inputs: Vec<(u16, i32)> = axes
                    .iter()
                    .map(|a| {
                        let sd = group.subdevice(&maindevice, a.unit).unwrap();
                        let i = sd.inputs_raw();
                        (
                            u16::from_le_bytes([i[a.statusword], i[a.statusword + 1]]),
                            i32_at(&i, a.position),
                        )
                    })
                    .collect();
                async_io::Timer::at(now + r.extra.next_cycle_wait).await;
                (r.working_counter, r.all_op(), inputs)
            }};
        }
        let deadline = Instant::now() + Duration::from_secs(5);
        loop {
            let (_, op, _) = cycle!();
            if op {
                break;
            }
            assert!(Instant::now() < deadline, "every SubDevice in Op");
        }
        let (wkc, _, _) = cycle!();
        assert_eq!(wkc, expected_wkc, "per unit: the LRW's read 1 + write 2");
        for (word, state) in [(0x0006u16, 0x0021u16), (0x0007, 0x0023), (0x000F, 0x0027)] {
            cw = [word; 5];
            let mut inputs = Vec::new();
            for _ in 0..20 {
                inputs = cycle!().2;
            }
            for (a, (sw, _)) in axes.iter().zip(&inputs) {
                assert_eq!(
                    sw & 0x006F,
                    state,
                    "{a:?}: statusword {sw:#06x} after {word:#06x}"
                );
            }
        }
        let goals: Vec<i32> = (0..5)
            .map(|n| (n + 1) * 500 * if n % 2 == 0 { 1 } else { -1 })
            .collect();
        for i in 1..=1000 {
            for n in 0..5 {
                targets[n] = goals[n] * i / 1000;
            }
            let (wkc, op, _) = cycle!();
            assert_eq!(wkc, expected_wkc);
            assert!(op, "still in Op");
        }
        // At rest: every axis at its goal for 100 cycles in a row (a servo that came in late, on a
        // loaded machine, may pass its goal by a count before it settles).
        let deadline = Instant::now() + Duration::from_secs(5);
        let mut held = 0;
        let last = loop {
            let (_, _, inputs) = cycle!();
            held = if inputs.iter().zip(&goals).all(|((_, p), g)| p == g) {
                held + 1
            } else {
                0
            };
            if held == 100 {
                break inputs;
            }
            assert!(
                Instant::now() < deadline,
                "every axis at its target: {inputs:?} of {goals:?}"
            );
        };
        for ((a, (sw, _)), goal) in axes.iter().zip(&last).zip(&goals) {
            assert_eq!(sw & 0x006F, 0x0027, "{a:?}: still Operation enabled");
            let sd = group.subdevice(&maindevice, a.unit).unwrap();
            let by_sdo: i32 = sd
                .sdo_read(0x6064 + 0x800 * a.number, 0)
                .await
                .expect("0x6064");
            assert_eq!(by_sdo, *goal, "{a:?}: 0x6064 by SDO");
        }
        let group = group.into_safe_op(&maindevice).await.expect("Op → Safe-Op");
        let group = group.into_pre_op(&maindevice).await.expect("→ Pre-Op");
        group.into_init(&maindevice).await.expect("→ Init");
    };
    async_io::block_on(future::or(scenario, tx_rx));
    eprintln!(
        "ethercrab: 4 units, 5 axes moved in csp with DC in {:?}",
        started.elapsed()
    );
    drop(link);
}
