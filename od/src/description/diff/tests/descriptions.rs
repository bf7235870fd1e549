use super::*;

/// A description with a part of every kind.
fn device() -> DeviceDescription {
    let entry = |index: u16, sub: u8, name: &str| PdoEntry {
        index,
        sub,
        bit_len: 1,
        name: name.into(),
        data_type: "BOOL".into(),
        ..PdoEntry::default()
    };
    let pdo = |index: u16, name: &str, entries: Vec<PdoEntry>| Pdo {
        index,
        name: name.into(),
        fixed: true,
        mandatory: false,
        sm: Some(3),
        exclude: vec![],
        entries,
        ..Pdo::default()
    };
    DeviceDescription {
        identity: Identity {
            vendor_id: 2,
            vendor_name: "Beckhoff".into(),
            product_code: 0x03F0_3052,
            revision: 0x0010_0000,
            product_name: "EL1008 8Ch. Dig. Input".into(),
            order_code: "EL1008".into(),
            ..Default::default()
        },
        file_info: FileInfo {
            file_name: "el1008.eds".into(),
            ..FileInfo::default()
        },
        can: Some(CanInfo {
            baud_rates: vec![125, 250],
            ..CanInfo::default()
        }),
        commissioning: None,
        ethercat: Some(EthercatInfo {
            group_type: "DigIn".into(),
            fmmus: vec!["Inputs".into()],
            sync_managers: vec![SyncManager {
                kind: "Inputs".into(),
                start_address: 0x1000,
                default_size: Some(1),
                min_size: None,
                max_size: None,
                control_byte: 0x00,
                enable: 1,
                ..SyncManager::default()
            }],
            rx_pdos: vec![],
            tx_pdos: vec![
                pdo(0x1A00, "Channel 1", vec![entry(0x6000, 1, "Input")]),
                pdo(0x1A01, "Channel 2", vec![entry(0x6010, 1, "Input")]),
            ],
            mailbox: Some(Mailbox {
                data_link_layer: false,
                coe: Some(CoeFlags {
                    sdo_info: true,
                    segmented_sdo: true,
                    ..CoeFlags::default()
                }),
                foe: false,
                eoe: false,
                init_cmds: vec![],
            }),
            op_modes: vec![
                OpMode {
                    name: "Synchron".into(),
                    desc: "SM-Synchron".into(),
                    ..OpMode::default()
                },
                OpMode {
                    name: "DC".into(),
                    desc: "DC-Synchron".into(),
                    assign_activate: 0x0300,
                    cycle_time_sync0: Some((0, 1)),
                    shift_time_sync0: Some(0),
                    cycle_time_sync1: None,
                    shift_time_sync1: None,
                },
            ],
            eeprom: Some(Eeprom {
                byte_size: 2048,
                config_data: vec![0x05, 0x06],
                boot_strap: vec![],
            }),
            slots: None,
            modules: Default::default(),
            root: EsiRoot::EtherCatInfo,
        }),
        dictionary: base(),
        comments: vec!["first".into(), "second".into()],
    }
}

fn device_diff(change: impl FnOnce(&mut DeviceDescription)) -> Vec<String> {
    let a = device();
    let mut b = device();
    change(&mut b);
    lines(&diff_devices(&a, &b))
}

fn ecat(d: &mut DeviceDescription) -> &mut EthercatInfo {
    d.ethercat.as_mut().unwrap()
}

#[test]
fn equal_descriptions_have_no_difference() {
    assert_eq!(device_diff(|_| {}), Vec::<String>::new());
    let empty = DeviceDescription::default();
    assert!(diff_devices(&empty, &empty).is_empty());
}

#[test]
fn identity_and_file_info_are_compared() {
    let text = device_diff(|b| {
        b.identity = Identity {
            vendor_id: 3,
            vendor_name: "B".into(),
            product_code: 4,
            revision: 5,
            product_name: "P".into(),
            order_code: "O".into(),
            ..Default::default()
        };
        b.file_info = FileInfo {
            file_name: "f".into(),
            file_version: "1".into(),
            file_revision: "2".into(),
            format_version: "4.0".into(),
            description: "d".into(),
            creation_time: "9:00AM".into(),
            creation_date: "01-02-2003".into(),
            created_by: "me".into(),
            modification_time: "10:00AM".into(),
            modification_date: "02-03-2004".into(),
            modified_by: "you".into(),
        };
    });
    assert_eq!(
        text,
        vec![
            "~ identity vendor ID: 0x00000002 -> 0x00000003",
            "~ identity vendor name: \"Beckhoff\" -> \"B\"",
            "~ identity product code: 0x03F03052 -> 0x00000004",
            "~ identity revision: 0x00100000 -> 0x00000005",
            "~ identity product name: \"EL1008 8Ch. Dig. Input\" -> \"P\"",
            "~ identity order code: \"EL1008\" -> \"O\"",
            "~ file info file name: \"el1008.eds\" -> \"f\"",
            "~ file info file version: \"\" -> \"1\"",
            "~ file info file revision: \"\" -> \"2\"",
            "~ file info format version: \"\" -> \"4.0\"",
            "~ file info description: \"\" -> \"d\"",
            "~ file info creation time: \"\" -> \"9:00AM\"",
            "~ file info creation date: \"\" -> \"01-02-2003\"",
            "~ file info created by: \"\" -> \"me\"",
            "~ file info modification time: \"\" -> \"10:00AM\"",
            "~ file info modification date: \"\" -> \"02-03-2004\"",
            "~ file info modified by: \"\" -> \"you\"",
        ]
    );
}

#[test]
fn can_info_commissioning_and_comments_are_compared() {
    let text = device_diff(|b| {
        b.can = Some(CanInfo {
            baud_rates: vec![],
            simple_boot_up_master: true,
            simple_boot_up_slave: false,
            granularity: 0,
            dynamic_channels: 1,
            group_messaging: true,
            nr_of_rx_pdo: 4,
            nr_of_tx_pdo: 5,
            lss_supported: true,
            dummy_usage: vec![2, 0x10],
        });
        b.commissioning = Some(Commissioning::default());
        b.comments = vec!["first".into(), "2nd".into(), "third".into()];
    });
    assert_eq!(
        text,
        vec![
            "~ CAN bit rates: 125 kbit/s, 250 kbit/s -> none",
            "~ CAN simple boot-up master: false -> true",
            "~ CAN simple boot-up slave: true -> false",
            "~ CAN granularity: 8 -> 0",
            "~ CAN dynamic channels: 0 -> 1",
            "~ CAN group messaging: false -> true",
            "~ CAN RPDOs: 0 -> 4",
            "~ CAN TPDOs: 0 -> 5",
            "~ CAN LSS: false -> true",
            "~ CAN dummy usage: none -> 0x0002, 0x0010",
            "+ commissioning",
            "~ comment 2 text: \"second\" -> \"2nd\"",
            "+ comment 3 third",
        ]
    );
    let mut a = device();
    a.commissioning = Some(Commissioning::default());
    let mut b = a.clone();
    b.can = None;
    b.commissioning = Some(Commissioning {
        node_id: Some(5),
        node_name: "n".into(),
        baud_rate: 500,
        net_number: 1,
        network_name: "net".into(),
        canopen_manager: true,
        lss_serial_number: 0x1234,
    });
    b.comments.clear();
    assert_eq!(
        lines(&diff_devices(&a, &b)),
        vec![
            "- CAN",
            "~ commissioning node ID: none -> 5",
            "~ commissioning node name: \"\" -> \"n\"",
            "~ commissioning bit rate: 0 kbit/s -> 500 kbit/s",
            "~ commissioning net number: 0 -> 1",
            "~ commissioning network name: \"\" -> \"net\"",
            "~ commissioning CANopen manager: false -> true",
            "~ commissioning LSS serial number: 0x00000000 -> 0x00001234",
            "- comment 1 first",
            "- comment 2 second",
        ]
    );
}

#[test]
fn ethercat_parts_are_compared() {
    let text = device_diff(|b| {
        let e = ecat(b);
        e.group_type = "DigOut".into();
        e.fmmus.push("MBoxState".into());
        e.sync_managers[0] = SyncManager {
            kind: "Outputs".into(),
            start_address: 0x0F00,
            default_size: None,
            min_size: Some(1),
            max_size: Some(2),
            control_byte: 0x64,
            enable: 9,
            is_virtual: true,
            op_only: true,
            watchdog: true,
        };
        e.sync_managers.push(SyncManager::default());
        let mb = e.mailbox.as_mut().unwrap();
        mb.data_link_layer = true;
        mb.coe = Some(CoeFlags {
            sdo_info: false,
            pdo_assign: true,
            pdo_config: true,
            pdo_upload: true,
            complete_access: true,
            segmented_sdo: false,
        });
        mb.foe = true;
        mb.eoe = true;
        e.eeprom = Some(Eeprom {
            byte_size: 256,
            config_data: vec![],
            boot_strap: vec![0x80],
        });
    });
    assert_eq!(
        text,
        vec![
            "~ group type: \"DigIn\" -> \"DigOut\"",
            "~ FMMUs: Inputs -> Inputs, MBoxState",
            "~ Sm 0 type: \"Inputs\" -> \"Outputs\"",
            "~ Sm 0 start address: 0x1000 -> 0x0F00",
            "~ Sm 0 default size: 1 -> none",
            "~ Sm 0 min size: none -> 1",
            "~ Sm 0 max size: none -> 2",
            "~ Sm 0 control byte: 0x00 -> 0x64",
            "~ Sm 0 enable: 1 -> 9",
            "~ Sm 0 virtual: false -> true",
            "~ Sm 0 op only: false -> true",
            "~ Sm 0 watchdog: false -> true",
            "+ Sm 1",
            "~ mailbox data link layer: false -> true",
            "~ mailbox CoE SDO info: true -> false",
            "~ mailbox CoE PDO assign: false -> true",
            "~ mailbox CoE PDO config: false -> true",
            "~ mailbox CoE PDO upload: false -> true",
            "~ mailbox CoE complete access: false -> true",
            "~ mailbox CoE segmented SDO: true -> false",
            "~ mailbox FoE: false -> true",
            "~ mailbox EoE: false -> true",
            "~ EEPROM byte size: 2048 -> 256",
            "~ EEPROM config data: 05 06 -> (empty)",
            "~ EEPROM boot strap: (empty) -> 80",
        ]
    );
    let text = device_diff(|b| {
        let e = ecat(b);
        e.fmmus.clear();
        e.sync_managers.clear();
        e.mailbox.as_mut().unwrap().coe = None;
        e.eeprom = None;
    });
    assert_eq!(
        text,
        vec![
            "~ FMMUs: Inputs -> none",
            "- Sm 0 Inputs",
            "- mailbox CoE",
            "- EEPROM",
        ]
    );
    let text = device_diff(|b| ecat(b).mailbox = None);
    assert_eq!(text, vec!["- mailbox"]);
    let text = device_diff(|b| b.ethercat = None);
    assert_eq!(text, vec!["- EtherCAT"]);
    let mut a = device();
    a.ethercat = None;
    assert_eq!(lines(&diff_devices(&a, &device())), vec!["+ EtherCAT"]);
}

#[test]
fn pdos_pair_by_index() {
    let text = device_diff(|b| {
        let e = ecat(b);
        let p = &mut e.tx_pdos[0];
        p.name = "Ch 1".into();
        p.fixed = false;
        p.mandatory = true;
        p.sm = None;
        p.index_depend.slot = true;
        p.is_virtual = true;
        p.su = Some(1);
        (p.os_factor, p.os_min, p.os_max, p.os_index_inc) = (Some(2), Some(3), Some(4), Some(16));
        p.exclude = vec![
            PdoRef {
                index: 0x1A01,
                depend: SlotDepend::default(),
            },
            PdoRef {
                index: 0x1A02,
                depend: SlotDepend {
                    slot: false,
                    slot_group: true,
                },
            },
        ];
        p.entries[0] = PdoEntry {
            index: 0x6000,
            index_depend: SlotDepend {
                slot: true,
                slot_group: true,
            },
            sub: 2,
            bit_len: 8,
            name: "In".into(),
            comment: "c".into(),
            data_type: "USINT".into(),
            data_scale: "0.1".into(),
            fixed: true,
        };
        p.entries.push(PdoEntry::default());
        e.tx_pdos[1].entries.clear();
        e.tx_pdos.push(Pdo {
            index: 0x1A02,
            name: "Status".into(),
            ..Pdo::default()
        });
        e.rx_pdos.push(Pdo {
            index: 0x1600,
            name: "Out".into(),
            ..Pdo::default()
        });
    });
    assert_eq!(
        text,
        vec![
            "+ RxPdo 0x1600 Out",
            "~ TxPdo 0x1A00 index depends on: none -> slot",
            "~ TxPdo 0x1A00 name: \"Channel 1\" -> \"Ch 1\"",
            "~ TxPdo 0x1A00 fixed: true -> false",
            "~ TxPdo 0x1A00 mandatory: false -> true",
            "~ TxPdo 0x1A00 virtual: false -> true",
            "~ TxPdo 0x1A00 Sm: 3 -> none",
            "~ TxPdo 0x1A00 Su: none -> 1",
            "~ TxPdo 0x1A00 OSFac: none -> 2",
            "~ TxPdo 0x1A00 OSMin: none -> 3",
            "~ TxPdo 0x1A00 OSMax: none -> 4",
            "~ TxPdo 0x1A00 OSIndexInc: none -> 16",
            "~ TxPdo 0x1A00 excludes: none -> 0x1A01, 0x1A02 (on slot group)",
            "~ TxPdo 0x1A00 entry 1 object: 0x6000:01 -> 0x6000:02",
            "~ TxPdo 0x1A00 entry 1 index depends on: none -> slot and slot group",
            "~ TxPdo 0x1A00 entry 1 bit length: 1 -> 8",
            "~ TxPdo 0x1A00 entry 1 name: \"Input\" -> \"In\"",
            "~ TxPdo 0x1A00 entry 1 comment: \"\" -> \"c\"",
            "~ TxPdo 0x1A00 entry 1 data type: \"BOOL\" -> \"USINT\"",
            "~ TxPdo 0x1A00 entry 1 data scale: \"\" -> \"0.1\"",
            "~ TxPdo 0x1A00 entry 1 fixed: false -> true",
            "+ TxPdo 0x1A00 entry 2 0x0000:00",
            "- TxPdo 0x1A01 entry 1 0x6010:01 Input",
            "+ TxPdo 0x1A02 Status",
        ]
    );
    let text = device_diff(|b| {
        let e = ecat(b);
        e.tx_pdos.swap(0, 1);
        e.tx_pdos.remove(1);
    });
    assert_eq!(text, vec!["- TxPdo 0x1A00 Channel 1"]);
}

#[test]
fn keyed_parts_in_another_order_are_one_difference() {
    let text = device_diff(|b| {
        let e = ecat(b);
        e.tx_pdos.swap(0, 1);
        e.op_modes.swap(0, 1);
    });
    assert_eq!(
        text,
        vec![
            "~ TxPdo order: 0x1A00, 0x1A01 -> 0x1A01, 0x1A00",
            "~ DC op mode order: Synchron, DC -> DC, Synchron",
        ]
    );
    // Only the order of the parts both have counts.
    let text = device_diff(|b| {
        let e = ecat(b);
        e.tx_pdos.reverse();
        e.tx_pdos.insert(
            1,
            Pdo {
                index: 0x1A05,
                ..Pdo::default()
            },
        );
        e.tx_pdos.insert(
            0,
            Pdo {
                index: 0x1A04,
                ..Pdo::default()
            },
        );
    });
    assert_eq!(
        text,
        vec![
            "+ TxPdo 0x1A04",
            "+ TxPdo 0x1A05",
            "~ TxPdo order: 0x1A00, 0x1A01 -> 0x1A01, 0x1A00",
        ]
    );
}

#[test]
fn parts_with_the_same_key_pair_in_their_order() {
    let mut a = device();
    let second = ecat(&mut a).tx_pdos[0].clone();
    ecat(&mut a).tx_pdos.push(second);
    let mut b = a.clone();
    ecat(&mut b).tx_pdos[2].name = "Again".into();
    assert_eq!(
        lines(&diff_devices(&a, &b)),
        vec!["~ TxPdo 0x1A00 #2 name: \"Channel 1\" -> \"Again\""]
    );
    ecat(&mut b).tx_pdos.remove(2);
    assert_eq!(
        lines(&diff_devices(&a, &b)),
        vec!["- TxPdo 0x1A00 #2 Channel 1"]
    );
}

#[test]
fn op_modes_pair_by_name() {
    let text = device_diff(|b| {
        let e = ecat(b);
        e.op_modes[1] = OpMode {
            name: "DC".into(),
            desc: "Distributed clocks".into(),
            assign_activate: 0x0700,
            cycle_time_sync0: None,
            shift_time_sync0: None,
            cycle_time_sync1: Some((1000, -1)),
            shift_time_sync1: Some(-50),
        };
        e.op_modes.remove(0);
        e.op_modes.push(OpMode {
            name: "Free".into(),
            desc: "Free run".into(),
            ..OpMode::default()
        });
    });
    assert_eq!(
        text,
        vec![
            "- DC op mode Synchron SM-Synchron",
            "~ DC op mode DC description: \"DC-Synchron\" -> \"Distributed clocks\"",
            "~ DC op mode DC assign activate: 0x0300 -> 0x0700",
            "~ DC op mode DC cycle time SYNC0: 0 ns, factor 1 -> none",
            "~ DC op mode DC shift time SYNC0: 0 ns -> none",
            "~ DC op mode DC cycle time SYNC1: none -> 1000 ns, factor -1",
            "~ DC op mode DC shift time SYNC1: none -> -50 ns",
            "+ DC op mode Free Free run",
        ]
    );
}

#[test]
fn all_parts_come_in_the_order_of_the_description() {
    let text = device_diff(|b| {
        b.identity.revision += 1;
        b.file_info.created_by = "x".into();
        b.can.as_mut().unwrap().lss_supported = true;
        b.commissioning = Some(Commissioning::default());
        ecat(b).eeprom = None;
        b.dictionary.remove(0x1000);
        b.comments.clear();
    });
    assert_eq!(
        text,
        vec![
            "~ identity revision: 0x00100000 -> 0x00100001",
            "~ file info created by: \"\" -> \"x\"",
            "~ CAN LSS: false -> true",
            "+ commissioning",
            "- EEPROM",
            "- 0x1000 Device type",
            "- comment 1 first",
            "- comment 2 second",
        ]
    );
}

#[test]
fn differences_tell_their_place() {
    let a = device();
    let mut b = device();
    sub(&mut b.dictionary, 0x1018, 1).name = "V".into();
    b.dictionary.object_mut(0x1000).unwrap().name = "T".into();
    ecat(&mut b).group_type = String::new();
    let d = diff_devices(&a, &b);
    assert_eq!(d.len(), 3);
    assert_eq!(
        (d[0].index(), d[0].sub(), d[0].place()),
        (None, None, String::new())
    );
    assert_eq!(
        (d[1].index(), d[1].sub(), d[1].place()),
        (Some(0x1000), None, "0x1000".to_string())
    );
    assert_eq!(
        (d[2].index(), d[2].sub(), d[2].place()),
        (Some(0x1018), Some(1), "0x1018:01".to_string())
    );
    assert_eq!(
        d[2].change,
        Change::Changed {
            field: "name",
            a: Shown::Text("Vendor-ID".into()),
            b: Shown::Text("V".into())
        }
    );
    assert_eq!(d[0].to_string(), "~ group type: \"DigIn\" -> \"\"");
    let pdo = Difference {
        path: vec![
            Step::Item {
                kind: "RxPdo",
                key: "0x1600".into(),
            },
            Step::Part("x"),
        ],
        change: Change::OnlyInA(String::new()),
    };
    assert_eq!((pdo.index(), pdo.sub()), (None, None));
    assert_eq!(pdo.to_string(), "- RxPdo 0x1600 x");
    assert_eq!(Shown::Text("a\"b".into()).as_str(), "a\"b");
    assert_eq!(Shown::Plain("0x01".into()).as_str(), "0x01");
}

fn named(name: &str, code: u32, revision: u32) -> DeviceDescription {
    let mut d = DeviceDescription::default();
    d.identity.order_code = name.into();
    d.identity.product_code = code;
    d.identity.revision = revision;
    d
}

#[test]
fn two_single_device_files_pair_their_devices() {
    assert_eq!(
        pair_devices(&[named("A", 1, 1)], &[named("B", 2, 2)]),
        vec![Pairing::Both(0, 0)]
    );
}

#[test]
fn devices_pair_by_product_code_and_revision() {
    let a = [named("A", 1, 1), named("B", 2, 1), named("C", 3, 1)];
    let b = [
        named("C", 3, 1),
        named("B2", 2, 1),
        named("A", 1, 2),
        named("D", 4, 1),
    ];
    assert_eq!(
        pair_devices(&a, &b),
        vec![
            Pairing::OnlyInA(0),
            Pairing::Both(1, 1),
            Pairing::Both(2, 0),
            Pairing::OnlyInB(2),
            Pairing::OnlyInB(3),
        ]
    );
    assert_eq!(pair_devices(&[], &b[..1]), vec![Pairing::OnlyInB(0)]);
    assert_eq!(pair_devices(&a[..1], &[]), vec![Pairing::OnlyInA(0)]);
}

#[test]
fn devices_that_share_code_and_revision_pair_by_name() {
    // Several demo devices with product code 0.
    let a = [named("X", 0, 0), named("Y", 0, 0), named("Z", 0, 0)];
    let b = [named("Z", 0, 0), named("W", 0, 0), named("X", 0, 0)];
    assert_eq!(
        pair_devices(&a, &b),
        vec![
            Pairing::Both(0, 2),
            Pairing::OnlyInA(1),
            Pairing::Both(2, 0),
            Pairing::OnlyInB(1),
        ]
    );
    // Repeated on one side only, and names that repeat too: each pairs once, in order.
    let a = [named("X", 0, 0), named("X", 0, 0)];
    let b = [named("X", 0, 0)];
    assert_eq!(
        pair_devices(&a, &b),
        vec![Pairing::Both(0, 0), Pairing::OnlyInA(1)]
    );
    let b = [named("X", 0, 0), named("Y", 0, 0), named("X", 0, 0)];
    assert_eq!(
        pair_devices(&a, &b),
        vec![
            Pairing::Both(0, 0),
            Pairing::Both(1, 2),
            Pairing::OnlyInB(1)
        ]
    );
    // Without a type name, the product name.
    let mut p = named("", 0, 0);
    p.identity.product_name = "Demo".into();
    let mut q = p.clone();
    q.identity.product_name = "Other".into();
    assert_eq!(
        pair_devices(&[p.clone(), q.clone()], &[q.clone(), p.clone()]),
        vec![Pairing::Both(0, 1), Pairing::Both(1, 0)]
    );
}

#[test]
fn steps_show_their_place() {
    assert_eq!(Step::Part("CAN").to_string(), "CAN");
    assert_eq!(
        Step::Item {
            kind: "Sm",
            key: "2".into()
        }
        .to_string(),
        "Sm 2"
    );
    assert_eq!(Step::Object(0x1A).to_string(), "0x001A");
    assert_eq!(Step::Entry(0x1A00, 0x1F).to_string(), "0x1A00:1F");
}

#[test]
fn slots_modules_and_start_up_commands_are_compared() {
    let text = device_diff(|b| {
        let e = ecat(b);
        e.slots = Some(Slots {
            max_slot_count: Some(4),
            ..Slots::default()
        });
        e.mailbox.as_mut().unwrap().init_cmds.push(InitCmd {
            transitions: vec!["PS".into()],
            index: 0x8000,
            sub: 1,
            data: vec![0x01, 0x00],
            comment: "mode".into(),
            ..InitCmd::default()
        });
        e.modules = vec![Module {
            ident: 0x0100_0001,
            type_name: "AI".into(),
            ..Module::default()
        }]
        .into();
    });
    assert_eq!(
        text,
        vec![
            "+ mailbox InitCmd 1 0x8000:01 mode",
            "+ Slots",
            "+ Module 0x01000001 AI",
        ]
    );
    let mut a = device();
    {
        let e = ecat(&mut a);
        e.slots = Some(Slots {
            slots: vec![Slot {
                name: "Slot 1".into(),
                max_instances: 1,
                ..Slot::default()
            }],
            module_pdo_groups: vec![ModulePdoGroup {
                name: "Inputs".into(),
                ..ModulePdoGroup::default()
            }],
            ..Slots::default()
        });
        e.mailbox.as_mut().unwrap().init_cmds.push(InitCmd {
            index: 0x8000,
            ..InitCmd::default()
        });
        e.modules = vec![Module {
            ident: 7,
            type_name: "AI".into(),
            ..Module::default()
        }]
        .into();
    }
    let mut b = a.clone();
    {
        let e = ecat(&mut b);
        let slots = e.slots.as_mut().unwrap();
        slots.max_slot_count = Some(8);
        slots.slot_index_increment = Some(16);
        slots.download_module_ident_list = true;
        slots.identify_module_by = "Ident".into();
        let slot = &mut slots.slots[0];
        slot.slot_group = Some(2);
        slot.min_instances = 1;
        slot.module_idents = vec![SlotModuleIdent {
            ident: 7,
            default: Some(1),
        }];
        slot.module_classes = vec![SlotModuleClass {
            class: "AI".into(),
            vendor_id: Some(2),
            name: "Analog".into(),
        }];
        slots.module_pdo_groups[0].rx_pdo = Some(0x1600);
        slots.module_pdo_groups[0].alignment = Some(2);
        let cmd = &mut e.mailbox.as_mut().unwrap().init_cmds[0];
        cmd.transitions = vec!["PS".into(), "SO".into()];
        cmd.sub = 2;
        cmd.data = vec![0xFF];
        cmd.complete_access = true;
        cmd.overwritten_by_module = true;
        let mut module = e.modules[0].clone();
        module.class = "AI".into();
        module.pdo_group = Some(0);
        module.name = "Analog input".into();
        module.profile_no = Some(5001);
        module.tx_pdos.push(Pdo {
            index: 0x1A00,
            name: "AI".into(),
            ..Pdo::default()
        });
        module.dc_op_mode_name = "DC".into();
        e.modules = vec![module].into();
    }
    b.dictionary
        .object_mut(0x1018)
        .and_then(|o| o.subs.get_mut(&1))
        .map(|s| s.value_plus_node_id = true)
        .expect("0x1018:01");
    assert_eq!(
        lines(&diff_devices(&a, &b)),
        vec![
            "~ mailbox InitCmd 1 transitions: none -> PS, SO",
            "~ mailbox InitCmd 1 object: 0x8000:00 -> 0x8000:02",
            "~ mailbox InitCmd 1 data: (empty) -> FF",
            "~ mailbox InitCmd 1 complete access: false -> true",
            "~ mailbox InitCmd 1 overwritten by module: false -> true",
            "~ Slots max slot count: none -> 8",
            "~ Slots slot index increment: none -> 16",
            "~ Slots download module ident list: false -> true",
            "~ Slots identify module by: \"\" -> \"Ident\"",
            "~ Slots Slot 1 slot group: none -> 2",
            "~ Slots Slot 1 min instances: 0 -> 1",
            "~ Slots Slot 1 module idents: none -> 0x00000007 (default 1)",
            "~ Slots Slot 1 module classes: none -> \"AI\" vendor 0x00000002 name \"Analog\"",
            "~ Slots ModulePdoGroup 1 alignment: none -> 2",
            "~ Slots ModulePdoGroup 1 RxPdo: none -> 0x1600",
            "~ Module 0x00000007 class: \"\" -> \"AI\"",
            "~ Module 0x00000007 PDO group: none -> 0",
            "~ Module 0x00000007 name: \"\" -> \"Analog input\"",
            "+ Module 0x00000007 TxPdo 0x1A00 AI",
            "~ Module 0x00000007 profile number: none -> 5001",
            "~ Module 0x00000007 DC op mode name: \"\" -> \"DC\"",
            "~ 0x1018:01 value relative to the node-ID: no -> yes",
        ]
    );
}

#[test]
fn a_module_of_a_catalogue_differs_from_a_device_and_by_its_module_parts() {
    let module = CatalogueModule {
        ident: 0x0009_1F84,
        class: "Di".into(),
        pdo_group: Some(1),
        profile_no: Some(5001),
        add_info: Some(0),
        dc_op_mode_name: String::new(),
    };
    let text = device_diff(|b| ecat(b).root = EsiRoot::EtherCatModule(module.clone()));
    assert_eq!(text, vec!["~ root element: EtherCATInfo -> EtherCATModule"]);
    let mut a = device();
    ecat(&mut a).root = EsiRoot::EtherCatModule(module.clone());
    let mut b = a.clone();
    ecat(&mut b).root = EsiRoot::EtherCatModule(CatalogueModule {
        ident: 0x0009_1F85,
        class: "Do".into(),
        pdo_group: None,
        profile_no: Some(5001),
        add_info: None,
        dc_op_mode_name: "DC".into(),
    });
    assert_eq!(
        lines(&diff_devices(&a, &b)),
        vec![
            "~ catalogue module module ident: 0x00091F84 -> 0x00091F85",
            "~ catalogue module class: \"Di\" -> \"Do\"",
            "~ catalogue module PDO group: 1 -> none",
            "~ catalogue module add info: 0 -> none",
            "~ catalogue module DC op mode name: \"\" -> \"DC\"",
        ]
    );
}
