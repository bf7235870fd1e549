//! Vendors' CiA 402 drives from the corpus beside the checkout (`../shared/corpus/esi`) as units of
//! `ethercat-node`, in process: what their ESIs give (process images worked out by hand from each
//! ESI's PDOs, drive axes), modules in slots, and each drive taken to Op with SYNC0, enabled by its
//! controlword and moved in csp to an exact position. A missing corpus fails the tests.

#[path = "common/node.rs"]
mod node;

use std::time::Duration;

use ethercat_slave::generic::{GenericUnit, Template, TemplateError};
use ethercat_slave::master::{Layout, SimChain};
use node::*;

/// Where a drive axis's objects are in its unit's process data (byte offsets).
#[derive(Clone, Copy)]
struct Axis {
    /// 0x6060, where the RxPDOs map it (else it is written by SDO).
    mode: Option<usize>,
    controlword: usize,
    target: usize,
    statusword: usize,
    position: usize,
}

fn le_at(b: &[u8], at: usize, n: usize) -> i64 {
    let mut v = [0u8; 8];
    v[..n].copy_from_slice(&b[at..at + n]);
    let raw = i64::from_le_bytes(v);
    (raw << (64 - 8 * n)) >> (64 - 8 * n)
}

/// Each unit to Op (SYNC0 1 ms on every unit), every axis enabled with its controlword, then a csp
/// ramp of `distance` counts over 1,000 cycles per axis (axis k overall by (k + 1) × distance, every
/// other one backwards): each ends exactly at its target, in the process data and by SDO (0x6064 of
/// its axis).
fn run_drives(units: &[(&Template, Vec<(u8, Axis)>)], distance: i64) {
    let list: Vec<(&Template, usize)> = units.iter().map(|(t, _)| (*t, 1)).collect();
    let layouts: Vec<Layout> = units.iter().map(|(t, _)| Layout::of(t)).collect();
    let mut c: SimChain<GenericUnit> = chain(&list);
    configure(&mut c, &layouts);
    let n = units.len() as u16;
    assert_eq!(request(&mut c, 0x02), n);
    c.cycle(Duration::from_millis(1));
    for (k, (_, axes)) in units.iter().enumerate() {
        for (axis, a) in axes {
            let base = 0x6000 + 0x800 * u16::from(*axis);
            if a.mode.is_none() {
                assert_eq!(
                    download(&mut c, &layouts[k], k, base + 0x60, 0, &[8]),
                    Ok(()),
                    "unit {k} 0x6060"
                );
            }
        }
        node::sync0(&mut c, k, 1_000_000, 500_000);
    }
    assert_eq!(request(&mut c, 0x04), n);
    for k in 0..units.len() {
        assert_eq!(al(&mut c, k), (0x04, 0), "unit {k} in Safe-Op");
    }
    let mut outputs: Vec<Vec<u8>> = layouts.iter().map(|l| vec![0; l.lengths().0]).collect();
    let put = |outputs: &mut Vec<Vec<u8>>, k: usize, at: usize, v: i64, n: usize| {
        outputs[k][at..at + n].copy_from_slice(&v.to_le_bytes()[..n]);
    };
    // csp in the process data where a unit maps 0x6060.
    for (k, (_, axes)) in units.iter().enumerate() {
        for (_, a) in axes {
            if let Some(at) = a.mode {
                put(&mut outputs, k, at, 8, 1);
            }
        }
    }
    lrw(&mut c, &layouts, &outputs);
    assert_eq!(request(&mut c, 0x08), n);
    let (wkc, mut inputs) = lrw(&mut c, &layouts, &outputs);
    assert_eq!(wkc, ethercat_slave::master::lrw_wkc(&layouts));
    for word in [0x0006u16, 0x0007, 0x000F] {
        for (k, (_, axes)) in units.iter().enumerate() {
            for (_, a) in axes {
                put(&mut outputs, k, a.controlword, i64::from(word), 2);
            }
        }
        for _ in 0..5 {
            inputs = lrw(&mut c, &layouts, &outputs).1;
        }
    }
    let mut moves = Vec::new();
    for (k, (_, axes)) in units.iter().enumerate() {
        for (_, a) in axes {
            assert_eq!(
                le_at(&inputs[k], a.statusword, 2) & 0x6F,
                0x27,
                "unit {k}: Operation enabled"
            );
            let start = le_at(&inputs[k], a.position, 4);
            let m = moves.len() as i64;
            let target = start + (m + 1) * distance * if m % 2 == 0 { 1 } else { -1 };
            moves.push((k, *a, start, target));
        }
    }
    for i in 1..=1000 {
        for &(k, a, start, target) in &moves {
            put(
                &mut outputs,
                k,
                a.target,
                start + (target - start) * i / 1000,
                4,
            );
        }
        let (wkc, _) = lrw(&mut c, &layouts, &outputs);
        assert_eq!(wkc, ethercat_slave::master::lrw_wkc(&layouts));
    }
    for _ in 0..300 {
        inputs = lrw(&mut c, &layouts, &outputs).1;
    }
    for &(k, a, _, target) in &moves {
        assert_eq!(
            le_at(&inputs[k], a.position, 4),
            target,
            "unit {k}: position in the process data"
        );
    }
    for (k, (_, axes)) in units.iter().enumerate() {
        for (axis, _) in axes {
            let base = 0x6000 + 0x800 * u16::from(*axis);
            let target = moves
                .iter()
                .find(|m| {
                    m.0 == k
                        && m.1.position == axes.iter().find(|x| x.0 == *axis).unwrap().1.position
                })
                .unwrap()
                .3;
            assert_eq!(
                read(&mut c, &layouts[k], k, base + 0x64, 0),
                target,
                "unit {k} axis {axis}: 0x6064"
            );
        }
    }
}

fn elmo() -> Template {
    template(&corpus("elmo-ECAT_00010420_V11.xml"), Some("0x00030924"))
}

fn ingenia() -> Template {
    template(&corpus("ingenia-eve-xcr-e.xml"), None)
}

fn copley() -> Template {
    template(&corpus("copley-XE2_4.60.xml"), None)
}

fn somanet() -> Template {
    template(&corpus("somanet-CiA402-single.xml"), None)
}

/// The process images and drive axes of each vendor's drive, from its ESI by hand:
/// - Elmo (0x00030924, newest revision 0x00010420): RxPDO 0x1600 (Sm 2) 0x607A (32), 0x60FE:01
///   (32), 0x6040 (16) = 10 bytes; TxPDO 0x1A00 (Sm 3) 0x6064, 0x60FD, 0x6041 = 10 bytes;
/// - Ingenia EVE-XCR-E: 0x1600 (Sm 2, default 4 entries) 0x6040, 0x607A, 0x60FF, 0x6060 = 11; 0x1A00
///   0x6041, 0x6064, 0x606C, 0x6061 = 11 (its 0x1C12:00 default 0 assigns nothing: the `Sm`
///   attributes do);
/// - Copley XE2, two slots with their default module "Cyclic position Mode" (0x10B00100): 0x1700
///   and 0x1740 (SlotPdoIncrement 64) each 0x6040 + 0x800·slot, 0x607A, 0x60B1, 0x60B2 = 12, 24 in
///   all; 0x1B00 and 0x1B40 each 0x6041, 0x6064, 0x60F4, 0x606C, 0x6077 = 16, 32 in all; axes A
///   and B;
/// - Synapticon SOMANET: 0x1600 (its dictionary's mapping, which maps 0x607A:00 where the PDO
///   element writes 0x607A:04) 0x6040, 0x6060, 0x6071, 0x607A, 0x60FF = 13; 0x1A00 0x6041, 0x6061,
///   0x6064, 0x606C, 0x6077 = 13.
#[test]
fn vendors_drives_as_their_esis_give_them() {
    for (t, lengths, axes, name) in [
        (elmo(), (10, 10), vec![0u8], "Elmo Drive"),
        (ingenia(), (11, 11), vec![0], "EVE-XCR-E"),
        (copley(), (24, 32), vec![0, 1], "XE2"),
        (somanet(), (13, 13), vec![0], "CiA402 Motor Control Device"),
    ] {
        assert_eq!(Layout::of(&t).lengths(), lengths, "{name}");
        assert_eq!(t.axes(), axes, "{name}");
        assert_eq!(t.name(), name);
    }
    assert_eq!(copley().modules(), [(0, 0x10B0_0100), (1, 0x10B0_0100)]);
}

/// Four vendors' drives in one chain (Elmo, Ingenia, Copley with two axes, Synapticon), in Op with
/// SYNC0, each axis in csp (by SDO where the RxPDO lacks 0x6060; Synapticon's 0x6060 is read-only
/// and mapped), enabled and moved: 5 axes at their targets exactly.
#[test]
fn four_vendors_drives_move_in_csp() {
    let (e, i, c, s) = (elmo(), ingenia(), copley(), somanet());
    let ax = |mode, controlword, target, statusword, position| Axis {
        mode,
        controlword,
        target,
        statusword,
        position,
    };
    run_drives(
        &[
            (&e, vec![(0, ax(None, 8, 0, 8, 0))]),
            (&i, vec![(0, ax(Some(10), 0, 2, 0, 2))]),
            (
                &c,
                vec![(0, ax(None, 0, 2, 0, 2)), (1, ax(None, 12, 14, 16, 18))],
            ),
            (&s, vec![(0, ax(Some(2), 0, 5, 0, 3))]),
        ],
        300,
    );
}

/// ETG.2001 modules in slots, as given: the Copley XE2 with "Cyclic velocity Mode" (0x10B00200:
/// RxPDO 0x1701 0x6040, 0x60FF, 0x60B2 = 8 bytes; TxPDO 0x1B00 16 bytes) in slot 1 and slot 2 empty;
/// the ETG.2001 example drive with "Velocity Mode (DC)" (0x0201: 0x1600 0x60FF, 0x6040 = 6; 0x1A00
/// 0x606C:01, 0x6041:01 = 6) and "Position Mode (DC)" (0x0101 in slot 2, PDOs and objects moved by
/// 16 and 0x800: 0x1610 0x687A, 0x6840; 0x1A10 0x6864:01, 0x6841:01) = 12 and 12, assigned in
/// slot order; by type name too. Refused with one line each: a module the ESI lacks, more modules
/// than slots, a module its slot does not take.
#[test]
fn modules_in_slots_as_given() {
    let path = corpus("copley-XE2_4.60.xml");
    let t = template_with(&path, None, Some(&["0x10b00200", "none"]));
    assert_eq!(Layout::of(&t).lengths(), (8, 16));
    assert_eq!(t.modules(), [(0, 0x10B0_0200)]);
    let by_name = template_with(&path, None, Some(&["cyclic velocity mode", "none"]));
    assert_eq!(by_name.modules(), t.modules());
    let etg = corpus("etg2001-ModulesSlots_CiA402.xml");
    let t = template_with(&etg, None, Some(&["0x0201", "#x0101"]));
    assert_eq!(Layout::of(&t).lengths(), (12, 12));
    let mut c = chain(&[(&t, 1)]);
    let layout = Layout::of(&t);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    assert_eq!(read(&mut c, &layout, 0, 0x1C12, 0), 2);
    assert_eq!(read(&mut c, &layout, 0, 0x1C12, 1), 0x1600);
    assert_eq!(read(&mut c, &layout, 0, 0x1C12, 2), 0x1610);
    assert_eq!(read(&mut c, &layout, 0, 0x1610, 1), 0x687A_0020);
    assert_eq!(read(&mut c, &layout, 0, 0x1A10, 2), 0x6841_0110);
    assert_eq!(read(&mut c, &layout, 0, 0x1C13, 2), 0x1A10);
    // The module's own objects, moved by the slot's index increment 0x800 (ETG.5001): slot 1's
    // target position 0x607A is 0x687A, its statusword 0x6041 (which the module maps as sub 1, so
    // a record with one entry) is 0x6841; Safe-Op maps them.
    assert_eq!(read(&mut c, &layout, 0, 0x687A, 0), 0);
    assert_eq!(read(&mut c, &layout, 0, 0x6841, 0), 1);
    request(&mut c, 0x04);
    assert_eq!(al(&mut c, 0), (0x04, 0));

    let refuse = |path: &std::path::Path, modules: &[&str]| {
        let spec = ethercat_slave::node_cli::EsiSpec {
            path: path.to_path_buf(),
            units: None,
            device: None,
            modules: Some(modules.iter().map(|s| s.to_string()).collect()),
        };
        ethercat_slave::node_cli::load(&spec)
            .unwrap_err()
            .to_string()
    };
    let unknown = refuse(&path, &["0x12345678"]);
    assert!(unknown.ends_with("XE2: no module \"0x12345678\" in the ESI (it has: 0x10b00100 Cyclic position Mode, 0x10b00200 Cyclic velocity Mode, 0x10b00300 Cyclic torque Mode, 0x10b00400 Cyclic torque with commutation angle Mode)"), "{unknown}");
    assert!(refuse(&path, &["none", "none", "0x10b00100"])
        .ends_with("XE2: 3 module(s) given, but the device has 2 slot(s)"));
    let bytes = std::fs::read(&path).unwrap();
    let mut desc = od::esi::read(&bytes, "copley", None).unwrap();
    let slots = desc.ethercat.as_mut().unwrap().slots.as_mut().unwrap();
    slots.slots[1]
        .module_idents
        .retain(|m| m.ident != 0x10B0_0300);
    let e = Template::new(desc, Some(&["none".into(), "0x10b00300".into()])).unwrap_err();
    assert!(matches!(
        e,
        TemplateError::ModuleNotInSlot {
            slot: 2,
            ident: 0x10B0_0300,
            ..
        }
    ));
    assert_eq!(
        e.to_string(),
        "XE2: slot 2 (Axis B) does not take module 0x10b00300; it takes 0x10b00100, 0x10b00200, 0x10b00400"
    );
}

/// ETG.2000 `WriteRestrictions`: an entry written only in Pre-Op is refused in Safe-Op with
/// 0x08000022 (the example drive's 0x6065 restricted for the test), and taken in Pre-Op.
#[test]
fn write_restrictions_are_kept_by_state() {
    let bytes = std::fs::read(root().join("examples/drive.esi.xml")).unwrap();
    let mut desc = od::esi::read(&bytes, "drive", None).unwrap();
    desc.dictionary
        .object_mut(0x6065)
        .unwrap()
        .subs
        .get_mut(&0)
        .unwrap()
        .access
        .write_states = Some(od::object::EcatStates::PREOP);
    let t = Template::new(desc, None).unwrap();
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    assert_eq!(
        download(&mut c, &layout, 0, 0x6065, 0, &500u32.to_le_bytes()),
        Ok(())
    );
    request(&mut c, 0x04);
    assert_eq!(al(&mut c, 0), (0x04, 0));
    assert_eq!(
        download(&mut c, &layout, 0, 0x6065, 0, &600u32.to_le_bytes()),
        Err(0x0800_0022)
    );
    assert_eq!(read(&mut c, &layout, 0, 0x6065, 0), 500);
    // Not restricted: 0x6066 is written in Safe-Op.
    assert_eq!(download(&mut c, &layout, 0, 0x6066, 0, &[20, 0]), Ok(()));
}

/// ETG.2000 `WriteRestrictions="SafeOp_Op"` (the example drive's 0x6067 restricted so for the
/// test): refused in Pre-Op with 0x08000022, taken in Safe-Op and in Op.
#[test]
fn write_restrictions_name_safe_op_and_op() {
    let bytes = std::fs::read(root().join("examples/drive.esi.xml")).unwrap();
    let mut desc = od::esi::read(&bytes, "drive", None).unwrap();
    desc.dictionary
        .object_mut(0x6067)
        .unwrap()
        .subs
        .get_mut(&0)
        .unwrap()
        .access
        .write_states = od::object::EcatStates::parse("SafeOp_Op");
    let t = Template::new(desc, None).unwrap();
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    assert_eq!(
        download(&mut c, &layout, 0, 0x6067, 0, &10u32.to_le_bytes()),
        Err(0x0800_0022)
    );
    request(&mut c, 0x04);
    assert_eq!(al(&mut c, 0), (0x04, 0));
    assert_eq!(
        download(&mut c, &layout, 0, 0x6067, 0, &20u32.to_le_bytes()),
        Ok(())
    );
    lrw(&mut c, std::slice::from_ref(&layout), &[vec![0; 7]]);
    request(&mut c, 0x08);
    assert_eq!(al(&mut c, 0), (0x08, 0));
    assert_eq!(
        download(&mut c, &layout, 0, 0x6067, 0, &30u32.to_le_bytes()),
        Ok(())
    );
    assert_eq!(read(&mut c, &layout, 0, 0x6067, 0), 30);
}

/// ETG.1000.6 §5.6.7.4, 0x1C00 (SyncManager communication types, UNSIGNED8: 1 mailbox out, 2
/// mailbox in, 3 process data outputs, 4 process data inputs, 0 unused) where the ESI's dictionary
/// has none, one entry per `Sm` element: the Ingenia EVE-XCR-E (MBoxOut, MBoxIn, Outputs, Inputs)
/// 4 entries 1, 2, 3, 4; the Pollen Orbita3d, which has an RxPDO assignment only (its TxPDOs at
/// 0x1700 and 0x1800 are no TxPDO mapping objects), MBoxOut, MBoxIn and two `Sm` named
/// `OrbitaIn`/`OrbitaOut`, none of the four kinds: 1, 2, 0, 0.
#[test]
fn sync_manager_types_where_the_esi_gives_none() {
    for (t, types) in [
        (ingenia(), [1u8, 2, 3, 4]),
        (template(&corpus("pollen-Orbita3d.xml"), None), [1, 2, 0, 0]),
    ] {
        let layout = Layout::of(&t);
        let mut c = chain(&[(&t, 1)]);
        configure(&mut c, std::slice::from_ref(&layout));
        request(&mut c, 0x02);
        let name = t.name();
        assert_eq!(upload(&mut c, &layout, 0, 0x1C00, 0), Ok(vec![4]), "{name}");
        for (sub, ty) in (1u8..).zip(types) {
            assert_eq!(
                upload(&mut c, &layout, 0, 0x1C00, sub),
                Ok(vec![ty]),
                "{name} 0x1C00:{sub:02X}"
            );
        }
    }
}

/// ETG.5001 module ident lists where the dictionary has them: the Inovance GL20-RTU-ECT32 coupler
/// (32 slots "Terminals") with slot 1 empty, GL20-0808ETN (0x10F41060) in slot 2 and GL20-3200END
/// (0x10F41011) in slot 3: 0xF030 (configured) and 0xF050 (detected) each count 3 slots, 0 for the
/// empty one, then the two idents.
#[test]
fn module_lists_name_each_slot_s_module() {
    let t = template_with(
        &corpus("lcec-INOVANCE_GL20_RTU_ECT32.xml"),
        None,
        Some(&["none", "0x10f41060", "0x10f41011"]),
    );
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    for index in [0xF030, 0xF050] {
        assert_eq!(read(&mut c, &layout, 0, index, 0), 3, "{index:04X}:00");
        assert_eq!(read(&mut c, &layout, 0, index, 1), 0, "{index:04X}:01");
        assert_eq!(
            read(&mut c, &layout, 0, index, 2),
            0x10F4_1060,
            "{index:04X}:02"
        );
        assert_eq!(
            read(&mut c, &layout, 0, index, 3),
            0x10F4_1011,
            "{index:04X}:03"
        );
        assert_eq!(read(&mut c, &layout, 0, index, 4), 0, "{index:04X}:04");
    }
}

/// Leaving Op ends the connection axis by axis, each as its own abort connection option code says
/// (CiA 402-2: axis A 0x6007, axis B 0x6807, 0x800 on): the Copley XE2, whose ESI gives both no
/// default (2, disable voltage, where never written), with 0x6807 = 1 (a fault with error code
/// 0x8100): after Op → Safe-Op axis A is Switch on disabled (0x6041 & 0x4F = 0x40), axis B Fault
/// (0x6841 & 0x4F = 0x08) with 0x683F = 0x8100.
#[test]
fn copley_axes_end_the_connection_each_as_its_option_code_says() {
    let t = copley();
    let layout = Layout::of(&t);
    let layouts = [layout.clone()];
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, &layouts);
    request(&mut c, 0x02);
    assert_eq!(
        download(&mut c, &layout, 0, 0x6807, 0, &1i16.to_le_bytes()),
        Ok(())
    );
    request(&mut c, 0x04);
    // Outputs: each slot's 0x6040 + 0x800·slot at bytes 0 and 12 (of 12 each); inputs: each slot's
    // statusword at bytes 0 and 16 (of 16 each).
    let mut outputs = vec![vec![0u8; 24]];
    lrw(&mut c, &layouts, &outputs);
    request(&mut c, 0x08);
    assert_eq!(al(&mut c, 0), (0x08, 0));
    let mut inputs = Vec::new();
    for cw in [0x0006u16, 0x0007, 0x000F] {
        outputs[0][0..2].copy_from_slice(&cw.to_le_bytes());
        outputs[0][12..14].copy_from_slice(&cw.to_le_bytes());
        for _ in 0..3 {
            inputs = lrw(&mut c, &layouts, &outputs).1;
        }
    }
    let status = |b: &[u8], at: usize| u16::from_le_bytes([b[at], b[at + 1]]);
    assert_eq!(
        status(&inputs[0], 0) & 0x6F,
        0x27,
        "axis A Operation enabled"
    );
    assert_eq!(
        status(&inputs[0], 16) & 0x6F,
        0x27,
        "axis B Operation enabled"
    );
    request(&mut c, 0x04);
    c.cycle(Duration::from_millis(50));
    assert_eq!(read(&mut c, &layout, 0, 0x6041, 0) & 0x4F, 0x40, "axis A");
    assert_eq!(read(&mut c, &layout, 0, 0x6841, 0) & 0x4F, 0x08, "axis B");
    assert_eq!(read(&mut c, &layout, 0, 0x683F, 0) & 0xFFFF, 0x8100);
}

/// ETG.1000.6 §5.6.7.4: the PDO configuration objects have the standard types, whatever the ESI
/// writes, and masters read them with those sizes: the Elmo drive's ESI gives its SyncManager types
/// as UINT (0x1C00:01–04 read as one byte each: 1, 2, 3, 4) and 0x1606's fifth and sixth entries as
/// INT and UINT (read as UNSIGNED32: 0x60B20010, 0x60400010, from its RxPdo 0x1606: 0x607A, 0x60FE:01,
/// 0x60FF, 0x60B1 of 32 bits, 0x60B2 and 0x6040 of 16); the example drive with its 0x1C12:01 given
/// as UDINT reads it as UNSIGNED16 0x1600.
#[test]
fn pdo_configuration_objects_have_the_standard_types() {
    let t = elmo();
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    for sub in 1..=4u8 {
        assert_eq!(upload(&mut c, &layout, 0, 0x1C00, sub), Ok(vec![sub]));
    }
    assert_eq!(
        upload(&mut c, &layout, 0, 0x1606, 5),
        Ok(0x60B2_0010u32.to_le_bytes().to_vec())
    );
    assert_eq!(
        upload(&mut c, &layout, 0, 0x1606, 6),
        Ok(0x6040_0010u32.to_le_bytes().to_vec())
    );

    let bytes = std::fs::read(root().join("examples/drive.esi.xml")).unwrap();
    let mut desc = od::esi::read(&bytes, "drive", None).unwrap();
    let entry = desc
        .dictionary
        .object_mut(0x1C12)
        .unwrap()
        .subs
        .get_mut(&1)
        .unwrap();
    entry.data_type = od::types::DataType::Unsigned32;
    entry.bit_size = od::types::DataType::Unsigned32.bit_size();
    entry.value = 0x1600u32.to_le_bytes().to_vec();
    let t = Template::new(desc, None).unwrap();
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    assert_eq!(upload(&mut c, &layout, 0, 0x1C12, 1), Ok(vec![0x00, 0x16]));
}

/// The PDO assignment at power-on: where the ESI's dictionary gives it, it stands over the PDOs'
/// `Sm` attributes (ETG.2000): the Beckhoff AX2000-B110 assigns 0x1701 (0x6062 of 32 bits, 0x6040
/// of 16: 6 bytes) and 0x1B01 (0x6064, 0x6041: 6 bytes) by its 0x1C12 and 0x1C13, not 0x1702 and
/// 0x1B03 of the `Sm` attributes. An assignment object the dictionary lacks is added for a direction
/// with PDOs only: the Pollen Orbita3d, whose only TxPDO-mapping-like PDOs sit at 0x1700 and 0x1800,
/// has 0x1C12 ("Sync Manager 2 PDO Assignment": one PDO, 0x1600 by its `Sm="2"`) and no 0x1C13
/// (0x06020000).
#[test]
fn power_on_assignments_as_the_esi_gives_them() {
    let bytes = std::fs::read(corpus("dls-Beckhoff_AX2xxx.xml")).unwrap();
    let desc = od::esi::read(&bytes, "ax2000", None).unwrap();
    let t = Template::new(desc, None).unwrap();
    let layout = Layout::of(&t);
    assert_eq!(layout.lengths(), (6, 6));
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    assert_eq!(read(&mut c, &layout, 0, 0x1C12, 0), 1);
    assert_eq!(read(&mut c, &layout, 0, 0x1C12, 1), 0x1701);
    assert_eq!(read(&mut c, &layout, 0, 0x1C13, 0), 1);
    assert_eq!(read(&mut c, &layout, 0, 0x1C13, 1), 0x1B01);

    let t = template(&corpus("pollen-Orbita3d.xml"), None);
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    assert_eq!(read(&mut c, &layout, 0, 0x1C12, 0), 1);
    assert_eq!(read(&mut c, &layout, 0, 0x1C12, 1), 0x1600);
    assert_eq!(upload(&mut c, &layout, 0, 0x1C13, 0), Err(0x0602_0000));
    assert_eq!(
        t.description().dictionary.object(0x1C12).unwrap().name,
        "Sync Manager 2 PDO Assignment"
    );
}

/// ETG.1000.6 §5.6.7.4: the mapping of a `Fixed` PDO is not changed, even where the dictionary
/// makes it writable and the device allows `PdoConfig`: the Elmo drive's first revision (0x00000001)
/// refuses 0x1600:00 in Pre-Op with 0x06010002.
#[test]
fn a_fixed_pdo_s_writable_mapping_is_refused() {
    let bytes = std::fs::read(corpus("elmo-ECAT_00010420_V11.xml")).unwrap();
    let desc = od::esi::read_all(&bytes, "elmo")
        .unwrap()
        .into_iter()
        .find(|d| d.identity.product_code == 0x0003_0924 && d.identity.revision == 1)
        .unwrap();
    let t = Template::new(desc, None).unwrap();
    let layout = Layout::of(&t);
    let mut c = chain(&[(&t, 1)]);
    configure(&mut c, std::slice::from_ref(&layout));
    request(&mut c, 0x02);
    assert_eq!(
        download(&mut c, &layout, 0, 0x1600, 0, &[0]),
        Err(0x0601_0002)
    );
}
