//! A unit's ESC has the FMMUs and SyncManagers its ESI gives (ETG.2000: the `Device/Fmmu` and
//! `Device/Sm` elements), no more: ESC information 0x0004 (FMMUs) and 0x0005 (SyncManagers) say how
//! many (ETG.1000.4 DL information; ESC datasheet section II table 1), and the register blocks of
//! the FMMUs (0x0600 + 16·n, ETG.1000.4 Table 57) and SyncManagers (0x0800 + 8·n, ETG.1000.4 §6.7)
//! past those counts are reserved: a write there is not taken, a read gives 0, and the datagram
//! counts in the working counter as any register access of the addressed ESC does (section I §2.4:
//! the ESC is addressed and the register area is not guarded by a SyncManager). An FMMU that does
//! not exist maps nothing: the process data goes through the existing ones only.
//!
//! Every exchange is a frame through the chain, in process on the simulated clock.

#[path = "common/node.rs"]
mod node;

use std::path::PathBuf;

use ethercat_slave::esc::cmd;
use ethercat_slave::frame::{CommandCode, Datagram};
use ethercat_slave::generic::GenericUnit;
use ethercat_slave::master::{self as m, Layout, SimChain};
use ethercat_slave::smd::binding::Device;
use node::*;

/// One register datagram to the chain: the data it came back with and its working counter.
fn reg<M: ethercat_slave::unit::Model>(
    c: &mut SimChain<M>,
    command: CommandCode,
    adp: u16,
    ado: u16,
    data: Vec<u8>,
) -> (Vec<u8>, u16) {
    let r = m::one(c, Datagram::new(command, adp, ado, data)).unwrap_or_else(|e| panic!("{e}"));
    (r.data, r.wkc)
}

/// One logical datagram to the chain: the data it came back with and its working counter.
fn logical(
    c: &mut SimChain<GenericUnit>,
    command: CommandCode,
    address: u32,
    data: Vec<u8>,
) -> (Vec<u8>, u16) {
    let r = one(
        c,
        Datagram {
            cmd: command,
            index: 0,
            address,
            data,
            wkc: 0,
        },
    );
    (r.data, r.wkc)
}

/// The ESC information 0x0000–0x0009 (ETG.1000.4 DL information) of a unit of each device, read by APRD
/// (one unit, position 0: WKC 1): type 0x11, revision 0, build 0x0002, FMMUs, SyncManagers, 60 KiB
/// of process RAM, ports 0 and 1 MII (0x0F), features 0x000D. Bytes 4 and 5 are the counts of the
/// ESI's `Fmmu` and `Sm` elements:
///
/// - the example I/O device and drive: Outputs, Inputs, MBoxState; MBoxOut, MBoxIn, Outputs,
///   Inputs: 3 and 4;
/// - EL6720: seven `Fmmu`, eight `Sm`: 7 and 8;
/// - AX5101-0000-0210: five `Fmmu` (two of them DynamicInputs/DynamicOutputs), six `Sm`: 5 and 6;
/// - AX2000-B110: five unnamed `Fmmu`, two `Sm` (Outputs, Inputs): 5 and 2;
/// - EL1004: one `Fmmu` (Inputs), one `Sm` (Inputs): 1 and 1;
/// - CU2508 (revision #x00110000, the newest of that name, as a device is picked by name): no
///   `Fmmu`, four `Sm` (MBoxOut, MBoxIn, Outputs, Inputs): with no FMMU list, one FMMU per
///   SyncManager that is not a mailbox's: 2, and 4.
#[test]
fn esc_information_counts_the_esis_fmmus_and_sync_managers() {
    let terminals = corpus("dls-Beckhoff_EtherCAT_Terminals.xml");
    let cases: [(PathBuf, Option<&str>, [u8; 10]); 7] = [
        (
            root().join("examples/io-device.esi.xml"),
            None,
            [0x11, 0x00, 0x02, 0x00, 0x03, 0x04, 0x3C, 0x0F, 0x0D, 0x00],
        ),
        (
            root().join("examples/drive.esi.xml"),
            None,
            [0x11, 0x00, 0x02, 0x00, 0x03, 0x04, 0x3C, 0x0F, 0x0D, 0x00],
        ),
        (
            corpus("dls-Beckhoff_EL67xx.xml"),
            Some("EL6720"),
            [0x11, 0x00, 0x02, 0x00, 0x07, 0x08, 0x3C, 0x0F, 0x0D, 0x00],
        ),
        (
            corpus("dls-Beckhoff_AX5xxx.xml"),
            Some("AX5101-0000-0210"),
            [0x11, 0x00, 0x02, 0x00, 0x05, 0x06, 0x3C, 0x0F, 0x0D, 0x00],
        ),
        (
            terminals.clone(),
            Some("AX2000-B110"),
            [0x11, 0x00, 0x02, 0x00, 0x05, 0x02, 0x3C, 0x0F, 0x0D, 0x00],
        ),
        (
            terminals,
            Some("EL1004"),
            [0x11, 0x00, 0x02, 0x00, 0x01, 0x01, 0x3C, 0x0F, 0x0D, 0x00],
        ),
        (
            corpus("dls-Beckhoff_CUxxxx.xml"),
            Some("CU2508"),
            [0x11, 0x00, 0x02, 0x00, 0x02, 0x04, 0x3C, 0x0F, 0x0D, 0x00],
        ),
    ];
    for (path, device, info) in cases {
        let t = template(&path, device);
        let mut c = chain(&[(&t, 1)]);
        let what = format!("{} {device:?}", path.display());
        assert_eq!(
            reg(&mut c, cmd::APRD, 0, 0x0000, vec![0; 10]),
            (info.to_vec(), 1),
            "{what}"
        );
        // The two counts alone, as a master reads them.
        assert_eq!(
            reg(&mut c, cmd::APRD, 0, 0x0004, vec![0; 2]),
            (info[4..6].to_vec(), 1),
            "{what}"
        );
    }
}

/// The SMD's fixture ESI gives three `Fmmu` (Outputs, Inputs, MBoxState) and four `Sm`: its ESC
/// information reads 0x11 0x00 0x02 0x00, 3 FMMUs, 4 SyncManagers, 0x3C 0x0F 0x0D 0x00, and FMMU 3
/// and SyncManager 4 are reserved (a write of 0xFF bytes taken with WKC 1, read back as 0).
#[test]
fn the_smd_has_its_fixtures_three_fmmus_and_four_sync_managers() {
    let mut c = SimChain::new(Device::Smd23kB, 1).unwrap();
    assert_eq!(
        reg(&mut c, cmd::APRD, 0, 0x0000, vec![0; 10]),
        (
            vec![0x11, 0x00, 0x02, 0x00, 0x03, 0x04, 0x3C, 0x0F, 0x0D, 0x00],
            1
        )
    );
    for (at, len) in [(0x0630u16, 16usize), (0x0820, 8)] {
        assert_eq!(
            reg(&mut c, cmd::APWR, 0, at, vec![0xFF; len]),
            (vec![0xFF; len], 1)
        );
        assert_eq!(
            reg(&mut c, cmd::APRD, 0, at, vec![0xEE; len]),
            (vec![0; len], 1)
        );
    }
    // The SMD comes up to Op as before and its outputs are the master's.
    m::bring_up(&mut c, 8).unwrap();
    let out = ds402::smd::indexer::Outputs {
        cmd0: 0x0002,
        position: 1000,
        ..Default::default()
    };
    let (wkc, _) = m::lrw(&mut c, &[out]).unwrap();
    assert_eq!(wkc, 3);
    assert_eq!(
        m::fprd(&mut c, 0, 0x1100, 20).unwrap(),
        (
            vec![2, 0, 0, 0, 0xE8, 0x03, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
            1
        )
    );
}

/// The example I/O device (3 FMMUs, 4 SyncManagers), register by register by APWR and APRD at
/// position 0 (WKC 1 for each, the ESC being addressed):
///
/// - FMMU 3 (0x0630): 16 bytes of 0x5A written, read back as 16 zeros;
/// - 32 bytes 0x01…0x20 over FMMUs 2 and 3 (0x0620): FMMU 2 takes 0x01…0x10, FMMU 3 reads 0;
/// - SyncManagers 3 and 4 (0x0818, 16 bytes): SM3 takes its start 0x1180, length 3, control 0x20,
///   activate 1 (its status and PDI control bytes are the slave's, 0); SM4's 8 bytes (a mailbox the
///   master writes, at 0x1200, 4 bytes, control 0x26, activated) read back 0, and that mailbox does
///   not exist: an APRD of 0x1200 is served (WKC 1), where a master-written mailbox would refuse it;
/// - FMMU 4 set to map logical 0x100 onto 0x1180 for reading, activated: it does not exist, and an
///   LRD of 3 bytes at 0x100 finds no FMMU (WKC 0, the frame's bytes unchanged).
#[test]
fn fmmus_and_sync_managers_past_the_esis_counts_are_reserved() {
    let t = io_device();
    let mut c = chain(&[(&t, 1)]);
    assert_eq!(
        reg(&mut c, cmd::APWR, 0, 0x0630, vec![0x5A; 16]),
        (vec![0x5A; 16], 1)
    );
    assert_eq!(
        reg(&mut c, cmd::APRD, 0, 0x0630, vec![0xEE; 16]),
        (vec![0; 16], 1)
    );
    let pattern: Vec<u8> = (0x01..=0x20).collect();
    assert_eq!(reg(&mut c, cmd::APWR, 0, 0x0620, pattern.clone()).1, 1);
    let mut expected = pattern[..16].to_vec();
    expected.extend_from_slice(&[0; 16]);
    assert_eq!(
        reg(&mut c, cmd::APRD, 0, 0x0620, vec![0; 32]),
        (expected, 1)
    );
    let sms = vec![
        0x80, 0x11, 0x03, 0x00, 0x20, 0xFF, 0x01, 0xFF, // SM3
        0x00, 0x12, 0x04, 0x00, 0x26, 0xFF, 0x01, 0xFF, // SM4
    ];
    assert_eq!(reg(&mut c, cmd::APWR, 0, 0x0818, sms).1, 1);
    assert_eq!(
        reg(&mut c, cmd::APRD, 0, 0x0818, vec![0; 16]),
        (
            vec![0x80, 0x11, 0x03, 0x00, 0x20, 0x00, 0x01, 0x00, 0, 0, 0, 0, 0, 0, 0, 0],
            1
        )
    );
    assert_eq!(
        reg(&mut c, cmd::APRD, 0, 0x1200, vec![0; 4]),
        (vec![0; 4], 1)
    );
    let fmmu4 = vec![
        0x00, 0x01, 0x00, 0x00, 0x03, 0x00, 0x00, 0x07, 0x80, 0x11, 0x00, 0x01, 0x01, 0x00, 0x00,
        0x00,
    ];
    assert_eq!(reg(&mut c, cmd::APWR, 0, 0x0640, fmmu4).1, 1);
    assert_eq!(
        logical(&mut c, cmd::LRD, 0x100, vec![0xEE; 3]),
        (vec![0xEE; 3], 0)
    );
}

/// FMMU 3 with garbage of the kind a confused master (or an attacker) leaves behind: logical 3 (where
/// a master puts the inputs of a one-unit image of 3 + 3 bytes), 3 bytes, start bit 0, end bit 7,
/// physical 0x1100 (the outputs SyncManager) bit 0, read and write, activated (ETG.1000.4 Table 57).
const GARBAGE: [u8; 16] = [
    0x03, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x07, 0x00, 0x11, 0x00, 0x03, 0x01, 0x00, 0x00, 0x00,
];

/// The example I/O device with that garbage written into FMMUs 3…15 (APWR, WKC 1 each), then the
/// start-up a master does that knows of 3 FMMUs (SOEM's `ecx_config_init`: BWR of 48 zero bytes at
/// 0x0600 for FMMUs 0–2 and 32 at 0x0800 for SyncManagers 0–3, WKC 1 each; then the SyncManagers and
/// FMMUs 0 and 1 of the layout): the FMMU registers 0x0600–0x06FF read back as FMMU 0 (logical 0, 3
/// bytes, bits 0–7, physical 0x1100, write, active), FMMU 1 (logical 3, 3 bytes, bits 0–7, physical
/// 0x1180, read, active) and 224 zeros; the unit goes through Pre-Op and Safe-Op to Op (AL status
/// 0x0008, code 0), and in Op an LRW of the outputs 0xA5 0x34 0x12 comes back with WKC 3 (2 for
/// the outputs written, 1 for the inputs read, ETG.1000.4 §5.4.3) and the inputs 0x84 0xFB 0xFF
/// (0x6000:03 and 0x6000:08 set, 0x6010:01 = −5). SM2's buffer at 0x1100 holds 0xA5 0x34 0x12, and
/// the unit took them: 0x7000:01–08 = 1 0 1 0 0 1 0 1, 0x7010:01 = 0x1234.
#[test]
fn garbage_in_fmmus_3_to_15_does_not_stop_a_restart_to_op() {
    let t = io_device();
    let layouts = [Layout::of(&t)];
    let layout = &layouts[0];
    assert_eq!(layout.lengths(), (3, 3));
    let mut c = chain(&[(&t, 1)]);
    for n in 3..16u16 {
        assert_eq!(
            reg(&mut c, cmd::APWR, 0, 0x0600 + 16 * n, GARBAGE.to_vec()).1,
            1,
            "FMMU {n}"
        );
    }
    assert_eq!(reg(&mut c, cmd::BWR, 0, 0x0600, vec![0; 48]).1, 1);
    assert_eq!(reg(&mut c, cmd::BWR, 0, 0x0800, vec![0; 32]).1, 1);
    configure(&mut c, &layouts);
    let mut registers = vec![
        0x00, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x07, 0x00, 0x11, 0x00, 0x02, 0x01, 0x00, 0x00,
        0x00, 0x03, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00, 0x07, 0x80, 0x11, 0x00, 0x01, 0x01, 0x00,
        0x00, 0x00,
    ];
    registers.resize(256, 0);
    assert_eq!(fprd(&mut c, 0, 0x0600, 256), (registers, 1));
    request(&mut c, 0x02);
    assert_eq!(al(&mut c, 0), (0x02, 0));
    request(&mut c, 0x04);
    assert_eq!(al(&mut c, 0), (0x04, 0));
    let now = c.now;
    let unit = c.chain.unit_mut(0).unwrap();
    unit.set(now, od::dict::Address::new(0x6000, 3), &[1])
        .unwrap();
    unit.set(now, od::dict::Address::new(0x6000, 8), &[1])
        .unwrap();
    unit.set(
        now,
        od::dict::Address::new(0x6010, 1),
        &(-5i16).to_le_bytes(),
    )
    .unwrap();
    let outputs = [vec![0xA5, 0x34, 0x12]];
    lrw(&mut c, &layouts, &outputs);
    request(&mut c, 0x08);
    assert_eq!(al(&mut c, 0), (0x08, 0));
    assert_eq!(
        lrw(&mut c, &layouts, &outputs),
        (3, vec![vec![0x84, 0xFB, 0xFF]])
    );
    assert_eq!(fprd(&mut c, 0, 0x1100, 3), (vec![0xA5, 0x34, 0x12], 1));
    let bits: Vec<i64> = (1..=8)
        .map(|s| read(&mut c, layout, 0, 0x7000, s))
        .collect();
    assert_eq!(bits, [1, 0, 1, 0, 0, 1, 0, 1]);
    assert_eq!(read(&mut c, layout, 0, 0x7010, 1), 0x1234);
    assert_eq!(al(&mut c, 0), (0x08, 0));
}

/// EK1101 (the newest revision of that name): one FMMU (Inputs) and one SyncManager (Inputs at
/// 0x1000; its one TxPDO maps the 16-bit ID switch 0x6000: 2 bytes). FMMUs 1…15 written with a write
/// mapping of logical 0, 2 bytes, onto 0x1F00 (process RAM no SyncManager guards), activated; then
/// the start-up of a master that knows of 3 FMMUs (BWR of 48 zero bytes at 0x0600 and 32 at 0x0800,
/// WKC 1 each), the layout's SyncManager and its one FMMU, FMMU 0 (logical 0, 2 bytes, bits 0–7,
/// physical 0x1000, read, active), Pre-Op, Safe-Op, Op. The LRW of the two input bytes comes back
/// with WKC 1 (the inputs read; no FMMU writes, ETG.1000.4 §5.4.3) and the switch's 0x0000, and
/// 0x1F00 stays 0.
#[test]
fn an_fmmu_past_the_count_adds_nothing_to_the_working_counter() {
    let t = template(&corpus("beckhoff-EK11xx.xml"), Some("EK1101"));
    let layouts = [Layout::of(&t)];
    assert_eq!(layouts[0].lengths(), (0, 2));
    let mut c = chain(&[(&t, 1)]);
    let garbage = vec![
        0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x07, 0x00, 0x1F, 0x00, 0x02, 0x01, 0x00, 0x00,
        0x00,
    ];
    for n in 1..16u16 {
        assert_eq!(
            reg(&mut c, cmd::APWR, 0, 0x0600 + 16 * n, garbage.clone()).1,
            1,
            "FMMU {n}"
        );
    }
    assert_eq!(reg(&mut c, cmd::BWR, 0, 0x0600, vec![0; 48]).1, 1);
    assert_eq!(reg(&mut c, cmd::BWR, 0, 0x0800, vec![0; 32]).1, 1);
    configure(&mut c, &layouts);
    let mut registers = vec![
        0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x07, 0x00, 0x10, 0x00, 0x01, 0x01, 0x00, 0x00,
        0x00,
    ];
    registers.resize(256, 0);
    assert_eq!(fprd(&mut c, 0, 0x0600, 256), (registers, 1));
    for state in [0x02, 0x04, 0x08] {
        request(&mut c, state);
        assert_eq!(al(&mut c, 0), (u16::from(state), 0));
    }
    assert_eq!(
        lrw(&mut c, &layouts, &[vec![]]),
        (1, vec![vec![0x00, 0x00]])
    );
    assert_eq!(fprd(&mut c, 0, 0x1F00, 2), (vec![0x00, 0x00], 1));
}
