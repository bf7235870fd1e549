//! The EtherCAT parts: the root element of the file (and what a module catalogue's module has beyond
//! a device's parts), group type, FMMUs, sync managers, PDOs, mailbox with its start-up commands, DC op
//! modes, EEPROM, slots and modules.

use super::context::{bytes_text, hex2, hex4, hex8, joined, or_none, Cx, Key, List};
use super::dictionary::dictionary;
use super::{Shown, Step};
use crate::device::{
    CatalogueModule, CoeFlags, Eeprom, EsiRoot, EthercatInfo, InitCmd, Mailbox, Module,
    ModulePdoGroup, OpMode, Pdo, PdoEntry, PdoRef, Slot, SlotDepend, SlotModuleClass,
    SlotModuleIdent, Slots, SyncManager,
};

/// The EtherCAT parts. A new list of parts is one more `cx.list` here with a compare function of its
/// own, as the PDOs and modules have.
pub(super) fn ethercat(cx: &mut Cx<'_>, a: &EthercatInfo, b: &EthercatInfo) {
    let EthercatInfo {
        group_type,
        fmmus,
        sync_managers,
        rx_pdos,
        tx_pdos,
        mailbox: mbox,
        op_modes,
        eeprom: rom,
        slots: slotted,
        modules: mods,
        root,
    } = a;
    cx.field("root element", root.element(), b.root.element(), |e| {
        Shown::Plain(e.to_string())
    });
    if let (EsiRoot::EtherCatModule(x), EsiRoot::EtherCatModule(y)) = (root, &b.root) {
        cx.within(Step::Part("catalogue module"), |cx| {
            catalogue_module(cx, x, y)
        });
    }
    cx.text("group type", group_type, &b.group_type);
    cx.field("FMMUs", fmmus, &b.fmmus, |v| joined(v, String::clone));
    cx.list(
        List {
            kind: "Sm",
            key: Key::Position(0),
            name: |s: &SyncManager| s.kind.clone(),
            compare: sync_manager,
        },
        sync_managers,
        &b.sync_managers,
    );
    pdos(cx, (rx_pdos, tx_pdos), (&b.rx_pdos, &b.tx_pdos));
    cx.option(Step::Part("mailbox"), mbox, &b.mailbox, mailbox);
    cx.list(
        List {
            kind: "DC op mode",
            key: Key::By {
                key: |m: &OpMode| m.name.clone(),
                order: "DC op mode order",
            },
            name: |m: &OpMode| m.desc.clone(),
            compare: op_mode,
        },
        op_modes,
        &b.op_modes,
    );
    cx.option(Step::Part("EEPROM"), rom, &b.eeprom, eeprom);
    cx.option(Step::Part("Slots"), slotted, &b.slots, slots);
    cx.list(
        List {
            kind: "Module",
            key: Key::By {
                key: |m: &Module| format!("0x{:08X}", m.ident),
                order: "Module order",
            },
            name: |m: &Module| m.type_name.clone(),
            compare: module,
        },
        mods,
        &b.modules,
    );
}

/// The receive and transmit PDOs of a device or a module, paired by index.
fn pdos(cx: &mut Cx<'_>, (rx, tx): (&[Pdo], &[Pdo]), (brx, btx): (&[Pdo], &[Pdo])) {
    for (kind, order, x, y) in [
        ("RxPdo", "RxPdo order", rx, brx),
        ("TxPdo", "TxPdo order", tx, btx),
    ] {
        cx.list(
            List {
                kind,
                key: Key::By {
                    key: |p: &Pdo| format!("0x{:04X}", p.index),
                    order,
                },
                name: |p: &Pdo| p.name.clone(),
                compare: pdo,
            },
            x,
            y,
        );
    }
}

fn number(v: &Option<u32>) -> Shown {
    Shown::Plain(or_none(v, u32::to_string))
}

fn depend(v: &SlotDepend) -> Shown {
    let SlotDepend { slot, slot_group } = v;
    Shown::Plain(
        match (slot, slot_group) {
            (false, false) => "none",
            (true, false) => "slot",
            (false, true) => "slot group",
            (true, true) => "slot and slot group",
        }
        .into(),
    )
}

fn slots(cx: &mut Cx<'_>, a: &Slots, b: &Slots) {
    let Slots {
        max_slot_count,
        max_slot_group_count,
        slot_pdo_increment,
        slot_group_pdo_increment,
        slot_index_increment,
        slot_group_index_increment,
        download_module_ident_list,
        identify_module_by,
        slots: each,
        module_pdo_groups,
    } = a;
    cx.field("max slot count", max_slot_count, &b.max_slot_count, number);
    cx.field(
        "max slot group count",
        max_slot_group_count,
        &b.max_slot_group_count,
        number,
    );
    increments(
        cx,
        [
            slot_pdo_increment,
            slot_group_pdo_increment,
            slot_index_increment,
            slot_group_index_increment,
        ],
        [
            &b.slot_pdo_increment,
            &b.slot_group_pdo_increment,
            &b.slot_index_increment,
            &b.slot_group_index_increment,
        ],
    );
    cx.plain(
        "download module ident list",
        download_module_ident_list,
        &b.download_module_ident_list,
    );
    cx.text(
        "identify module by",
        identify_module_by,
        &b.identify_module_by,
    );
    cx.list(
        List {
            kind: "Slot",
            key: Key::Position(1),
            name: |s: &Slot| s.name.clone(),
            compare: slot,
        },
        each,
        &b.slots,
    );
    cx.list(
        List {
            kind: "ModulePdoGroup",
            key: Key::Position(1),
            name: |g: &ModulePdoGroup| g.name.clone(),
            compare: module_pdo_group,
        },
        module_pdo_groups,
        &b.module_pdo_groups,
    );
}

/// The PDO and index increments per slot and slot group, which `Slots` gives for all slots and a `Slot`
/// for itself.
fn increments(cx: &mut Cx<'_>, a: [&Option<u32>; 4], b: [&Option<u32>; 4]) {
    let fields = [
        "slot PDO increment",
        "slot group PDO increment",
        "slot index increment",
        "slot group index increment",
    ];
    for ((field, x), y) in fields.into_iter().zip(a).zip(b) {
        cx.field(field, x, y, number);
    }
}

fn slot(cx: &mut Cx<'_>, a: &Slot, b: &Slot) {
    let Slot {
        name,
        slot_group,
        min_instances,
        max_instances,
        slot_pdo_increment,
        slot_group_pdo_increment,
        slot_index_increment,
        slot_group_index_increment,
        tree_view,
        module_idents,
        module_classes,
    } = a;
    cx.text("name", name, &b.name);
    cx.field("slot group", slot_group, &b.slot_group, number);
    cx.plain("min instances", min_instances, &b.min_instances);
    cx.plain("max instances", max_instances, &b.max_instances);
    increments(
        cx,
        [
            slot_pdo_increment,
            slot_group_pdo_increment,
            slot_index_increment,
            slot_group_index_increment,
        ],
        [
            &b.slot_pdo_increment,
            &b.slot_group_pdo_increment,
            &b.slot_index_increment,
            &b.slot_group_index_increment,
        ],
    );
    cx.text("tree view", tree_view, &b.tree_view);
    cx.field("module idents", module_idents, &b.module_idents, |v| {
        joined(v, |m: &SlotModuleIdent| {
            let SlotModuleIdent { ident, default } = m;
            match default {
                Some(d) => format!("0x{ident:08X} (default {d})"),
                None => format!("0x{ident:08X}"),
            }
        })
    });
    cx.field("module classes", module_classes, &b.module_classes, |v| {
        joined(v, |m: &SlotModuleClass| {
            let SlotModuleClass {
                class,
                vendor_id,
                name,
            } = m;
            let vendor = or_none(vendor_id, |v| format!("0x{v:08X}"));
            format!("{class:?} vendor {vendor} name {name:?}")
        })
    });
}

fn module_pdo_group(cx: &mut Cx<'_>, a: &ModulePdoGroup, b: &ModulePdoGroup) {
    let ModulePdoGroup {
        name,
        alignment,
        rx_pdo,
        tx_pdo,
    } = a;
    let index = |v: &Option<u16>| Shown::Plain(or_none(v, |i| format!("0x{i:04X}")));
    cx.text("name", name, &b.name);
    cx.field("alignment", alignment, &b.alignment, number);
    cx.field("RxPdo", rx_pdo, &b.rx_pdo, index);
    cx.field("TxPdo", tx_pdo, &b.tx_pdo, index);
}

fn module(cx: &mut Cx<'_>, a: &Module, b: &Module) {
    let Module {
        ident: _, // the key the modules were paired by
        class,
        pdo_group,
        type_name,
        name,
        rx_pdos,
        tx_pdos,
        mailbox: mbox,
        profile_no,
        add_info,
        dictionary: dict,
        dc_op_mode_name,
    } = a;
    cx.text("class", class, &b.class);
    cx.field("PDO group", pdo_group, &b.pdo_group, number);
    cx.text("type", type_name, &b.type_name);
    cx.text("name", name, &b.name);
    pdos(cx, (rx_pdos, tx_pdos), (&b.rx_pdos, &b.tx_pdos));
    cx.option(Step::Part("mailbox"), mbox, &b.mailbox, mailbox);
    cx.field("profile number", profile_no, &b.profile_no, number);
    cx.field("add info", add_info, &b.add_info, number);
    dictionary(cx, dict, &b.dictionary);
    cx.text("DC op mode name", dc_op_mode_name, &b.dc_op_mode_name);
}

/// What a module of a module catalogue has beyond the description's parts.
fn catalogue_module(cx: &mut Cx<'_>, a: &CatalogueModule, b: &CatalogueModule) {
    let CatalogueModule {
        ident,
        class,
        pdo_group,
        profile_no,
        add_info,
        dc_op_mode_name,
    } = a;
    cx.field("module ident", ident, &b.ident, hex8);
    cx.text("class", class, &b.class);
    cx.field("PDO group", pdo_group, &b.pdo_group, number);
    cx.field("profile number", profile_no, &b.profile_no, number);
    cx.field("add info", add_info, &b.add_info, number);
    cx.text("DC op mode name", dc_op_mode_name, &b.dc_op_mode_name);
}

fn sync_manager(cx: &mut Cx<'_>, a: &SyncManager, b: &SyncManager) {
    let SyncManager {
        kind,
        start_address,
        default_size,
        min_size,
        max_size,
        control_byte,
        enable,
        is_virtual,
        op_only,
        watchdog,
    } = a;
    let size = |v: &Option<u16>| Shown::Plain(or_none(v, u16::to_string));
    cx.text("type", kind, &b.kind);
    cx.field("start address", start_address, &b.start_address, hex4);
    cx.field("default size", default_size, &b.default_size, size);
    cx.field("min size", min_size, &b.min_size, size);
    cx.field("max size", max_size, &b.max_size, size);
    cx.field("control byte", control_byte, &b.control_byte, hex2);
    cx.plain("enable", enable, &b.enable);
    cx.plain("virtual", is_virtual, &b.is_virtual);
    cx.plain("op only", op_only, &b.op_only);
    cx.plain("watchdog", watchdog, &b.watchdog);
}

fn pdo(cx: &mut Cx<'_>, a: &Pdo, b: &Pdo) {
    let Pdo {
        index: _, // the key the PDOs were paired by
        index_depend,
        name,
        fixed,
        mandatory,
        is_virtual,
        sm,
        su,
        os_factor,
        os_min,
        os_max,
        os_index_inc,
        exclude,
        entries,
    } = a;
    let small = |v: &Option<u8>| Shown::Plain(or_none(v, u8::to_string));
    cx.field("index depends on", index_depend, &b.index_depend, depend);
    cx.text("name", name, &b.name);
    cx.plain("fixed", fixed, &b.fixed);
    cx.plain("mandatory", mandatory, &b.mandatory);
    cx.plain("virtual", is_virtual, &b.is_virtual);
    cx.field("Sm", sm, &b.sm, small);
    cx.field("Su", su, &b.su, small);
    cx.field("OSFac", os_factor, &b.os_factor, number);
    cx.field("OSMin", os_min, &b.os_min, number);
    cx.field("OSMax", os_max, &b.os_max, number);
    cx.field("OSIndexInc", os_index_inc, &b.os_index_inc, number);
    cx.field("excludes", exclude, &b.exclude, |v| {
        joined(v, |r: &PdoRef| {
            let PdoRef { index, depend: on } = r;
            match depend(on).as_str() {
                "none" => format!("0x{index:04X}"),
                d => format!("0x{index:04X} (on {d})"),
            }
        })
    });
    cx.list(
        List {
            kind: "entry",
            key: Key::Position(1),
            name: |e: &PdoEntry| {
                format!("0x{:04X}:{:02X} {}", e.index, e.sub, e.name)
                    .trim_end()
                    .to_string()
            },
            compare: pdo_entry,
        },
        entries,
        &b.entries,
    );
}

fn pdo_entry(cx: &mut Cx<'_>, a: &PdoEntry, b: &PdoEntry) {
    let PdoEntry {
        index,
        index_depend,
        sub,
        bit_len,
        name,
        comment,
        data_type,
        data_scale,
        fixed,
    } = a;
    cx.field("object", &(*index, *sub), &(b.index, b.sub), |(i, s)| {
        Shown::Plain(format!("0x{i:04X}:{s:02X}"))
    });
    cx.field("index depends on", index_depend, &b.index_depend, depend);
    cx.plain("bit length", bit_len, &b.bit_len);
    cx.text("name", name, &b.name);
    cx.text("comment", comment, &b.comment);
    cx.text("data type", data_type, &b.data_type);
    cx.text("data scale", data_scale, &b.data_scale);
    cx.plain("fixed", fixed, &b.fixed);
}

fn mailbox(cx: &mut Cx<'_>, a: &Mailbox, b: &Mailbox) {
    let Mailbox {
        data_link_layer,
        coe: flags,
        foe,
        eoe,
        init_cmds,
    } = a;
    cx.plain("data link layer", data_link_layer, &b.data_link_layer);
    cx.option(Step::Part("CoE"), flags, &b.coe, coe);
    cx.plain("FoE", foe, &b.foe);
    cx.plain("EoE", eoe, &b.eoe);
    cx.list(
        List {
            kind: "InitCmd",
            key: Key::Position(1),
            name: |c: &InitCmd| {
                format!("0x{:04X}:{:02X} {}", c.index, c.sub, c.comment)
                    .trim_end()
                    .to_string()
            },
            compare: init_cmd,
        },
        init_cmds,
        &b.init_cmds,
    );
}

fn init_cmd(cx: &mut Cx<'_>, a: &InitCmd, b: &InitCmd) {
    let InitCmd {
        transitions,
        index,
        index_depend,
        sub,
        data,
        adapt_automatically,
        comment,
        fixed,
        complete_access,
        overwritten_by_module,
    } = a;
    cx.field("transitions", transitions, &b.transitions, |v| {
        joined(v, String::clone)
    });
    cx.field("object", &(*index, *sub), &(b.index, b.sub), |(i, s)| {
        Shown::Plain(format!("0x{i:04X}:{s:02X}"))
    });
    cx.field("index depends on", index_depend, &b.index_depend, depend);
    cx.field("data", data, &b.data, |v| Shown::Plain(bytes_text(v)));
    cx.plain(
        "adapt automatically",
        adapt_automatically,
        &b.adapt_automatically,
    );
    cx.text("comment", comment, &b.comment);
    cx.plain("fixed", fixed, &b.fixed);
    cx.plain("complete access", complete_access, &b.complete_access);
    cx.plain(
        "overwritten by module",
        overwritten_by_module,
        &b.overwritten_by_module,
    );
}

fn coe(cx: &mut Cx<'_>, a: &CoeFlags, b: &CoeFlags) {
    let CoeFlags {
        sdo_info,
        pdo_assign,
        pdo_config,
        pdo_upload,
        complete_access,
        segmented_sdo,
    } = a;
    cx.plain("SDO info", sdo_info, &b.sdo_info);
    cx.plain("PDO assign", pdo_assign, &b.pdo_assign);
    cx.plain("PDO config", pdo_config, &b.pdo_config);
    cx.plain("PDO upload", pdo_upload, &b.pdo_upload);
    cx.plain("complete access", complete_access, &b.complete_access);
    cx.plain("segmented SDO", segmented_sdo, &b.segmented_sdo);
}

fn op_mode(cx: &mut Cx<'_>, a: &OpMode, b: &OpMode) {
    let OpMode {
        name: _, // the key the op modes were paired by
        desc,
        assign_activate,
        cycle_time_sync0,
        shift_time_sync0,
        cycle_time_sync1,
        shift_time_sync1,
    } = a;
    let cycle = |v: &Option<(u32, i32)>| {
        Shown::Plain(or_none(v, |(ns, factor)| {
            format!("{ns} ns, factor {factor}")
        }))
    };
    let shift = |v: &Option<i32>| Shown::Plain(or_none(v, |ns| format!("{ns} ns")));
    cx.text("description", desc, &b.desc);
    cx.field("assign activate", assign_activate, &b.assign_activate, hex4);
    cx.field(
        "cycle time SYNC0",
        cycle_time_sync0,
        &b.cycle_time_sync0,
        cycle,
    );
    cx.field(
        "shift time SYNC0",
        shift_time_sync0,
        &b.shift_time_sync0,
        shift,
    );
    cx.field(
        "cycle time SYNC1",
        cycle_time_sync1,
        &b.cycle_time_sync1,
        cycle,
    );
    cx.field(
        "shift time SYNC1",
        shift_time_sync1,
        &b.shift_time_sync1,
        shift,
    );
}

fn eeprom(cx: &mut Cx<'_>, a: &Eeprom, b: &Eeprom) {
    let Eeprom {
        byte_size,
        config_data,
        boot_strap,
    } = a;
    let bytes = |v: &Vec<u8>| Shown::Plain(bytes_text(v));
    cx.plain("byte size", byte_size, &b.byte_size);
    cx.field("config data", config_data, &b.config_data, bytes);
    cx.field("boot strap", boot_strap, &b.boot_strap, bytes);
}
