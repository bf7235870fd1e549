//! The ESI writer: one `EtherCATInfo` document from descriptions (an `EtherCATModule` one from the
//! modules of a module catalogue), through [`XmlWriter`] so the output is
//! byte-stable (fixed element order, objects and types in index order, no dates).

use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap};

use crate::device::{
    CatalogueModule, DeviceDescription, EsiRoot, EthercatInfo, InitCmd, Mailbox, Module, Pdo,
    PdoEntry, SlotDepend, Slots, SyncManager,
};
use crate::dict::Dictionary;
use crate::object::{Access, AccessType, Object, ObjectKind, PdoMapping, SubObject};
use crate::types::DataType;
use crate::xml::XmlWriter;

const DERIVED_NOTE: &str = "No EtherCAT part in the source description. Derived: RxPdo/TxPdo from the \
mapping objects 0x1600-0x17FF/0x1A00-0x1BFF and their default mapping, the four standard sync managers, \
FMMUs and a CoE mailbox.";

pub(super) fn write_all(descs: &[DeviceDescription]) -> String {
    let catalogue: Option<Vec<(&DeviceDescription, &EthercatInfo, &CatalogueModule)>> = descs
        .iter()
        .map(|d| match &d.ethercat {
            Some(e) => match &e.root {
                EsiRoot::EtherCatModule(m) => Some((d, e, m)),
                _ => None,
            },
            None => None,
        })
        .collect();
    let list = !descs.is_empty()
        && descs.iter().all(|d| {
            matches!(
                d.ethercat.as_ref().map(|e| &e.root),
                Some(EsiRoot::EtherCatInfoList(_))
            )
        });
    match catalogue {
        Some(modules) if !modules.is_empty() => write_catalogue(&modules),
        _ if list => write_list(descs),
        _ => {
            let mut w = XmlWriter::new();
            write_info(&mut w, descs);
            w.finish()
        }
    }
}

/// An `EtherCATInfoList`: one `EtherCATInfo` per run of descriptions of the same entry of the list.
fn write_list(descs: &[DeviceDescription]) -> String {
    let entry = |d: &DeviceDescription| match d.ethercat.as_ref().map(|e| &e.root) {
        Some(EsiRoot::EtherCatInfoList(n)) => *n,
        _ => 0,
    };
    let mut w = XmlWriter::new();
    w.start("EtherCATInfoList", &[]);
    for run in descs.chunk_by(|a, b| entry(a) == entry(b)) {
        write_info(&mut w, run);
    }
    w.end();
    w.finish()
}

/// The root element and the `Vendor` of the first description.
fn start_file(w: &mut XmlWriter, root: &str, schema: &str, first: Option<&DeviceDescription>) {
    w.start(
        root,
        &[
            ("xmlns:xsi", "http://www.w3.org/2001/XMLSchema-instance"),
            ("xsi:noNamespaceSchemaLocation", schema),
            ("Version", "1.11"),
        ],
    );
    let vendor_id = first.map_or(0, |d| d.identity.vendor_id);
    let vendor_name = first.map_or("", |d| d.identity.vendor_name.as_str());
    let file_version = first.map_or("", |d| d.file_info.file_version.as_str());
    if file_version.is_empty() {
        w.start("Vendor", &[]);
    } else {
        w.start("Vendor", &[("FileVersion", file_version)]);
    }
    w.text("Id", &[], &hex32(vendor_id));
    w.text("Name", &[("LcId", "1033")], vendor_name);
    w.end();
}

/// A module catalogue (ETG.2000 module description): `EtherCATModule` with the vendor and one
/// `Modules/Module` per description, in the parts a module has.
fn write_catalogue(modules: &[(&DeviceDescription, &EthercatInfo, &CatalogueModule)]) -> String {
    let mut w = XmlWriter::new();
    start_file(
        &mut w,
        "EtherCATModule",
        "EtherCATModule.xsd",
        modules.first().map(|m| m.0),
    );
    w.start("Modules", &[]);
    for (desc, ecat, m) in modules {
        let parts = ModuleParts {
            ident: m.ident,
            class: &m.class,
            pdo_group: m.pdo_group,
            type_name: &desc.identity.order_code,
            name: &desc.identity.product_name,
            rx_pdos: &ecat.rx_pdos,
            tx_pdos: &ecat.tx_pdos,
            mailbox: ecat.mailbox.as_ref(),
            profile_no: m.profile_no,
            add_info: m.add_info,
            dictionary: &desc.dictionary,
            dc_op_mode_name: &m.dc_op_mode_name,
        };
        write_module(&mut w, &parts, node_id(desc));
    }
    w.end();
    w.finish()
}

/// An `EtherCATInfo` element: one `Device` per description (a module of a catalogue among devices is
/// written as a device), then the modules of the devices.
fn write_info(w: &mut XmlWriter, descs: &[DeviceDescription]) {
    let first = descs.first();
    start_file(w, "EtherCATInfo", "EtherCATInfo.xsd", first);
    w.start("Descriptions", &[]);
    let ecats: Vec<Cow<EthercatInfo>> = descs
        .iter()
        .map(|d| match &d.ethercat {
            Some(e) => Cow::Borrowed(e),
            None => Cow::Owned(super::derive::derive_ethercat(d)),
        })
        .collect();
    let mut groups: Vec<&str> = Vec::new();
    for e in &ecats {
        if !groups.contains(&e.group_type.as_str()) {
            groups.push(&e.group_type);
        }
    }
    w.start("Groups", &[]);
    for g in &groups {
        w.start("Group", &[]);
        w.text("Type", &[], g);
        w.text("Name", &[("LcId", "1033")], g);
        w.end();
    }
    w.end();
    w.start("Devices", &[]);
    for (desc, ecat) in descs.iter().zip(&ecats) {
        write_device(w, desc, ecat, desc.ethercat.is_none());
    }
    w.end();
    // Each device of a file carries the file's modules (one shared list): the first list is written as
    // it is, then what other lists have that it does not.
    let mut lists: Vec<&std::sync::Arc<[Module]>> = Vec::new();
    let mut modules: Vec<&Module> = Vec::new();
    for e in &ecats {
        if lists.iter().any(|l| std::sync::Arc::ptr_eq(l, &e.modules)) {
            continue;
        }
        if lists.is_empty() {
            modules.extend(e.modules.iter());
        } else {
            for m in e.modules.iter() {
                if !modules.contains(&m) {
                    modules.push(m);
                }
            }
        }
        lists.push(&e.modules);
    }
    if !modules.is_empty() {
        let node = first.map_or(0, node_id);
        w.start("Modules", &[]);
        for m in modules {
            write_module(w, &ModuleParts::of(m), node);
        }
        w.end();
    }
    w.end(); // Descriptions
    w.end(); // EtherCATInfo
}

/// The parts of a `Module` element (ETG.2001 `ModuleType`), from a [`Module`] of an `EtherCATInfo` or
/// from a description of a module catalogue.
struct ModuleParts<'a> {
    ident: u32,
    class: &'a str,
    pdo_group: Option<u32>,
    type_name: &'a str,
    name: &'a str,
    rx_pdos: &'a [Pdo],
    tx_pdos: &'a [Pdo],
    mailbox: Option<&'a Mailbox>,
    profile_no: Option<u32>,
    add_info: Option<u32>,
    dictionary: &'a Dictionary,
    dc_op_mode_name: &'a str,
}

impl<'a> ModuleParts<'a> {
    fn of(m: &'a Module) -> ModuleParts<'a> {
        ModuleParts {
            ident: m.ident,
            class: &m.class,
            pdo_group: m.pdo_group,
            type_name: &m.type_name,
            name: &m.name,
            rx_pdos: &m.rx_pdos,
            tx_pdos: &m.tx_pdos,
            mailbox: m.mailbox.as_ref(),
            profile_no: m.profile_no,
            add_info: m.add_info,
            dictionary: &m.dictionary,
            dc_op_mode_name: &m.dc_op_mode_name,
        }
    }
}

fn write_module(w: &mut XmlWriter, m: &ModuleParts, node: u8) {
    w.start("Module", &[]);
    let ident = hex32(m.ident);
    let group = m.pdo_group.map(|g| g.to_string());
    let mut attrs: Vec<(&str, &str)> = vec![("ModuleIdent", &ident)];
    if !m.class.is_empty() {
        attrs.push(("ModuleClass", m.class));
    }
    if let Some(g) = &group {
        attrs.push(("ModulePdoGroup", g));
    }
    w.text("Type", &attrs, m.type_name);
    w.text("Name", &[("LcId", "1033")], m.name);
    for p in m.rx_pdos {
        write_pdo(w, "RxPdo", p);
    }
    for p in m.tx_pdos {
        write_pdo(w, "TxPdo", p);
    }
    if let Some(mb) = m.mailbox {
        write_mailbox(w, mb);
    }
    w.start("Profile", &[]);
    if let Some(n) = m.profile_no {
        w.text("ProfileNo", &[], &n.to_string());
    }
    if let Some(n) = m.add_info {
        w.text("AddInfo", &[], &n.to_string());
    }
    write_dictionary(w, m.dictionary, node);
    w.end();
    if !m.dc_op_mode_name.is_empty() {
        w.text("DcOpModeName", &[], m.dc_op_mode_name);
    }
    w.end();
}

fn opt_attr<'a>(attrs: &mut Vec<(&'a str, String)>, name: &'a str, v: Option<u32>) {
    if let Some(v) = v {
        attrs.push((name, v.to_string()));
    }
}

fn write_slots(w: &mut XmlWriter, s: &Slots) {
    let mut owned: Vec<(&str, String)> = Vec::new();
    opt_attr(&mut owned, "MaxSlotCount", s.max_slot_count);
    opt_attr(&mut owned, "MaxSlotGroupCount", s.max_slot_group_count);
    opt_attr(&mut owned, "SlotPdoIncrement", s.slot_pdo_increment);
    opt_attr(
        &mut owned,
        "SlotGroupPdoIncrement",
        s.slot_group_pdo_increment,
    );
    opt_attr(&mut owned, "SlotIndexIncrement", s.slot_index_increment);
    opt_attr(
        &mut owned,
        "SlotGroupIndexIncrement",
        s.slot_group_index_increment,
    );
    if s.download_module_ident_list {
        owned.push(("DownloadModuleIdentList", "1".to_string()));
    }
    if !s.identify_module_by.is_empty() {
        owned.push(("IdentifyModuleBy", s.identify_module_by.clone()));
    }
    let attrs: Vec<(&str, &str)> = owned.iter().map(|(k, v)| (*k, v.as_str())).collect();
    w.start("Slots", &attrs);
    for slot in &s.slots {
        let mut owned: Vec<(&str, String)> = Vec::new();
        opt_attr(&mut owned, "SlotGroup", slot.slot_group);
        owned.push(("MinInstances", slot.min_instances.to_string()));
        owned.push(("MaxInstances", slot.max_instances.to_string()));
        opt_attr(&mut owned, "SlotPdoIncrement", slot.slot_pdo_increment);
        opt_attr(
            &mut owned,
            "SlotGroupPdoIncrement",
            slot.slot_group_pdo_increment,
        );
        opt_attr(&mut owned, "SlotIndexIncrement", slot.slot_index_increment);
        opt_attr(
            &mut owned,
            "SlotGroupIndexIncrement",
            slot.slot_group_index_increment,
        );
        if !slot.tree_view.is_empty() {
            owned.push(("TreeView", slot.tree_view.clone()));
        }
        let attrs: Vec<(&str, &str)> = owned.iter().map(|(k, v)| (*k, v.as_str())).collect();
        w.start("Slot", &attrs);
        if !slot.name.is_empty() {
            w.text("Name", &[("LcId", "1033")], &slot.name);
        }
        for m in &slot.module_idents {
            match m.default {
                Some(d) => w.text(
                    "ModuleIdent",
                    &[("Default", &d.to_string())],
                    &hex32(m.ident),
                ),
                None => w.text("ModuleIdent", &[], &hex32(m.ident)),
            };
        }
        for c in &slot.module_classes {
            w.start("ModuleClass", &[]);
            w.text("Class", &[], &c.class);
            if let Some(v) = c.vendor_id {
                w.text("VendorId", &[], &hex32(v));
            }
            if !c.name.is_empty() {
                w.text("Name", &[("LcId", "1033")], &c.name);
            }
            w.end();
        }
        w.end();
    }
    for g in &s.module_pdo_groups {
        let mut owned: Vec<(&str, String)> = Vec::new();
        opt_attr(&mut owned, "Alignment", g.alignment);
        if let Some(p) = g.rx_pdo {
            owned.push(("RxPdo", hex16(p)));
        }
        if let Some(p) = g.tx_pdo {
            owned.push(("TxPdo", hex16(p)));
        }
        let attrs: Vec<(&str, &str)> = owned.iter().map(|(k, v)| (*k, v.as_str())).collect();
        w.text("ModulePdoGroup", &attrs, &g.name);
    }
    w.end();
}

fn hex32(v: u32) -> String {
    format!("#x{v:08X}")
}

fn hex16(v: u16) -> String {
    format!("#x{v:04X}")
}

fn hex_bytes(bytes: &[u8]) -> String {
    let mut s = String::with_capacity(bytes.len() * 2);
    for b in bytes {
        s.push_str(&format!("{b:02X}"));
    }
    s
}

fn bool_text(b: bool) -> &'static str {
    if b {
        "true"
    } else {
        "false"
    }
}

fn write_device(w: &mut XmlWriter, desc: &DeviceDescription, ecat: &EthercatInfo, derived: bool) {
    w.start("Device", &[]);
    if derived {
        w.comment(DERIVED_NOTE);
    }
    let id = &desc.identity;
    w.text(
        "Type",
        &[
            ("ProductCode", &hex32(id.product_code)),
            ("RevisionNo", &hex32(id.revision)),
        ],
        &id.order_code,
    );
    w.text("Name", &[("LcId", "1033")], &id.product_name);
    w.text("GroupType", &[], &ecat.group_type);
    w.start("Profile", &[]);
    write_dictionary(w, &desc.dictionary, node_id(desc));
    w.end();
    for f in &ecat.fmmus {
        w.text("Fmmu", &[], f);
    }
    for sm in &ecat.sync_managers {
        write_sm(w, sm);
    }
    for p in &ecat.rx_pdos {
        write_pdo(w, "RxPdo", p);
    }
    for p in &ecat.tx_pdos {
        write_pdo(w, "TxPdo", p);
    }
    if let Some(mb) = &ecat.mailbox {
        write_mailbox(w, mb);
    }
    if !ecat.op_modes.is_empty() {
        w.start("Dc", &[]);
        for m in &ecat.op_modes {
            w.start("OpMode", &[]);
            w.text("Name", &[], &m.name);
            w.text("Desc", &[], &m.desc);
            w.text("AssignActivate", &[], &hex16(m.assign_activate));
            for (sync, cycle, shift) in [
                (0, m.cycle_time_sync0, m.shift_time_sync0),
                (1, m.cycle_time_sync1, m.shift_time_sync1),
            ] {
                if let Some((t, f)) = cycle {
                    w.text(
                        &format!("CycleTimeSync{sync}"),
                        &[("Factor", &f.to_string())],
                        &t.to_string(),
                    );
                }
                if let Some(t) = shift {
                    w.text(&format!("ShiftTimeSync{sync}"), &[], &t.to_string());
                }
            }
            w.end();
        }
        w.end();
    }
    if let Some(s) = &ecat.slots {
        write_slots(w, s);
    }
    if let Some(ee) = &ecat.eeprom {
        w.start("Eeprom", &[]);
        w.text("ByteSize", &[], &ee.byte_size.to_string());
        w.text("ConfigData", &[], &hex_bytes(&ee.config_data));
        if !ee.boot_strap.is_empty() {
            w.text("BootStrap", &[], &hex_bytes(&ee.boot_strap));
        }
        w.end();
    }
    w.end();
}

fn write_sm(w: &mut XmlWriter, sm: &SyncManager) {
    let min = sm.min_size.map(|v| v.to_string());
    let max = sm.max_size.map(|v| v.to_string());
    let def = sm.default_size.map(|v| v.to_string());
    let start = hex16(sm.start_address);
    let control = format!("#x{:02X}", sm.control_byte);
    let mut attrs: Vec<(&str, &str)> = Vec::new();
    if let Some(v) = &min {
        attrs.push(("MinSize", v));
    }
    if let Some(v) = &max {
        attrs.push(("MaxSize", v));
    }
    if let Some(v) = &def {
        attrs.push(("DefaultSize", v));
    }
    attrs.push(("StartAddress", &start));
    attrs.push(("ControlByte", &control));
    let enable = sm.enable.to_string();
    attrs.push(("Enable", &enable));
    for (on, name) in [
        (sm.is_virtual, "Virtual"),
        (sm.op_only, "OpOnly"),
        (sm.watchdog, "Watchdog"),
    ] {
        if on {
            attrs.push((name, "1"));
        }
    }
    w.text("Sm", &attrs, &sm.kind);
}

/// The `DependOnSlot`/`DependOnSlotGroup` attributes of an index.
fn depend_attrs(d: SlotDepend) -> Vec<(&'static str, &'static str)> {
    let mut attrs = Vec::new();
    if d.slot {
        attrs.push(("DependOnSlot", "true"));
    }
    if d.slot_group {
        attrs.push(("DependOnSlotGroup", "true"));
    }
    attrs
}

fn write_pdo(w: &mut XmlWriter, element: &str, p: &Pdo) {
    let numbers: Vec<(&str, String)> = [
        ("Sm", p.sm.map(u32::from)),
        ("Su", p.su.map(u32::from)),
        ("OSFac", p.os_factor),
        ("OSMin", p.os_min),
        ("OSMax", p.os_max),
        ("OSIndexInc", p.os_index_inc),
    ]
    .into_iter()
    .filter_map(|(k, v)| v.map(|v| (k, v.to_string())))
    .collect();
    let mut attrs: Vec<(&str, &str)> = Vec::new();
    for (on, name) in [
        (p.fixed, "Fixed"),
        (p.mandatory, "Mandatory"),
        (p.is_virtual, "Virtual"),
    ] {
        if on {
            attrs.push((name, "1"));
        }
    }
    attrs.extend(numbers.iter().map(|(k, v)| (*k, v.as_str())));
    w.start(element, &attrs);
    w.text("Index", &depend_attrs(p.index_depend), &hex16(p.index));
    w.text("Name", &[], &p.name);
    for x in &p.exclude {
        w.text("Exclude", &depend_attrs(x.depend), &hex16(x.index));
    }
    for e in &p.entries {
        write_entry(w, e);
    }
    w.end();
}

fn write_entry(w: &mut XmlWriter, e: &PdoEntry) {
    if e.fixed {
        w.start("Entry", &[("Fixed", "1")]);
    } else {
        w.start("Entry", &[]);
    }
    w.text("Index", &depend_attrs(e.index_depend), &hex16(e.index));
    if e.index != 0 || e.sub != 0 {
        w.text("SubIndex", &[], &e.sub.to_string());
    }
    w.text("BitLen", &[], &e.bit_len.to_string());
    if !e.name.is_empty() {
        w.text("Name", &[], &e.name);
    }
    if !e.comment.is_empty() {
        w.text("Comment", &[], &e.comment);
    }
    if !e.data_type.is_empty() || !e.data_scale.is_empty() {
        if e.data_scale.is_empty() {
            w.text("DataType", &[], &e.data_type);
        } else {
            w.text("DataType", &[("DScale", &e.data_scale)], &e.data_type);
        }
    }
    w.end();
}

fn write_mailbox(w: &mut XmlWriter, mb: &Mailbox) {
    if mb.data_link_layer {
        w.start("Mailbox", &[("DataLinkLayer", "true")]);
    } else {
        w.start("Mailbox", &[]);
    }
    if mb.eoe {
        w.empty("EoE", &[]);
    }
    if let Some(c) = &mb.coe {
        let attrs = [
            ("SdoInfo", bool_text(c.sdo_info)),
            ("PdoAssign", bool_text(c.pdo_assign)),
            ("PdoConfig", bool_text(c.pdo_config)),
            ("PdoUpload", bool_text(c.pdo_upload)),
            ("CompleteAccess", bool_text(c.complete_access)),
            ("SegmentedSdo", bool_text(c.segmented_sdo)),
        ];
        if mb.init_cmds.is_empty() {
            w.empty("CoE", &attrs);
        } else {
            w.start("CoE", &attrs);
            for cmd in &mb.init_cmds {
                write_init_cmd(w, cmd);
            }
            w.end();
        }
    }
    if mb.foe {
        w.empty("FoE", &[]);
    }
    w.end();
}

fn write_init_cmd(w: &mut XmlWriter, cmd: &InitCmd) {
    let mut attrs: Vec<(&str, &str)> = Vec::new();
    for (on, name) in [
        (cmd.fixed, "Fixed"),
        (cmd.complete_access, "CompleteAccess"),
        (cmd.overwritten_by_module, "OverwrittenByModule"),
    ] {
        if on {
            attrs.push((name, "true"));
        }
    }
    w.start("InitCmd", &attrs);
    for t in &cmd.transitions {
        w.text("Transition", &[], t);
    }
    w.text("Index", &depend_attrs(cmd.index_depend), &hex16(cmd.index));
    w.text("SubIndex", &[], &cmd.sub.to_string());
    if cmd.adapt_automatically {
        w.text(
            "Data",
            &[("AdaptAutomatically", "true")],
            &hex_bytes(&cmd.data),
        );
    } else {
        w.text("Data", &[], &hex_bytes(&cmd.data));
    }
    if !cmd.comment.is_empty() {
        w.text("Comment", &[], &cmd.comment);
    }
    w.end();
}

// ---------------------------------------------------------------------------------------------------------
// Dictionary.

/// The node-ID `$NODEID` defaults are resolved for (a DCF's), else 0: the plain offset.
fn node_id(desc: &DeviceDescription) -> u8 {
    desc.node_id().unwrap_or(0)
}

/// Size in bits the ESI gives an entry: the type's, else its capacity, else the default's length.
fn entry_bits(sub: &SubObject) -> u32 {
    if let Some(b) = sub.data_type.bit_size() {
        return b;
    }
    if let Some(b) = sub.bit_size {
        return b;
    }
    let len = sub
        .default
        .as_ref()
        .and_then(|d| d.value.encode(sub.data_type).ok())
        .map_or(sub.value.len(), |b| b.len());
    let unit = if sub.data_type == DataType::UnicodeString {
        16
    } else {
        8
    };
    u32::try_from(len)
        .unwrap_or(u32::MAX / 16)
        .saturating_mul(8)
        .div_ceil(unit)
        * unit
}

fn entry_type_name(sub: &SubObject) -> String {
    sub.data_type.esi_name(entry_bits(sub))
}

fn access_text(kind: AccessType) -> &'static str {
    match kind {
        AccessType::Ro | AccessType::Const => "ro",
        AccessType::Wo => "wo",
        AccessType::Rw | AccessType::Rwr | AccessType::Rww => "rw",
    }
}

fn pdo_text(p: PdoMapping) -> Option<&'static str> {
    match p {
        PdoMapping::None => None,
        PdoMapping::Rpdo => Some("R"),
        PdoMapping::Tpdo => Some("T"),
        PdoMapping::Both => Some("RT"),
    }
}

fn write_flags(w: &mut XmlWriter, access: Access, pdo: PdoMapping) {
    w.start("Flags", &[]);
    let read = access.read_states.map(|s| s.to_string());
    let write = access.write_states.map(|s| s.to_string());
    let mut attrs: Vec<(&str, &str)> = Vec::new();
    if let Some(r) = &read {
        attrs.push(("ReadRestrictions", r));
    }
    if let Some(wr) = &write {
        attrs.push(("WriteRestrictions", wr));
    }
    w.text("Access", &attrs, access_text(access.kind));
    if let Some(p) = pdo_text(pdo) {
        w.text("PdoMapping", &[], p);
    }
    w.end();
}

/// One `SubItem` of a structure type.
#[derive(Debug, Clone, PartialEq)]
struct Item {
    sub: u8,
    name: String,
    type_name: String,
    comment: Option<String>,
    bit_size: u32,
    bit_offs: u32,
    access: Access,
    pdo: PdoMapping,
}

/// The `…ARR` type of an array: base type, element size, count (from sub-index 1).
#[derive(Debug, Clone, PartialEq)]
struct Arr {
    base: String,
    element_bits: u32,
    elements: u32,
}

/// A structure type as the ESI writes it.
#[derive(Debug, Clone, PartialEq)]
struct Struct {
    bit_size: u32,
    /// Sub-index 0, then (arrays) the `Elements` item or (records) every entry.
    items: Vec<Item>,
    arr: Option<Arr>,
}

fn item_of(sub_index: u8, sub: &SubObject, bit_offs: u32) -> Item {
    Item {
        sub: sub_index,
        name: sub.name.clone(),
        type_name: entry_type_name(sub),
        comment: sub.description.clone(),
        bit_size: entry_bits(sub),
        bit_offs,
        access: sub.access,
        pdo: sub.pdo,
    }
}

/// The structure type of a RECORD or ARRAY object, standard CoE layout: sub-index 0 at bit 0, sub-index 1
/// at bit 16 (after a wider sub-index 0, such as DS301's UNSIGNED32 in 0x1004, at the next 16-bit
/// boundary after it), the rest packed.
fn struct_of(object: &Object) -> Struct {
    let mut items = Vec::new();
    let mut offset: u32 = 16;
    if let Some(zero) = object.subs.get(&0) {
        let item = item_of(0, zero, 0);
        offset = offset.max(item.bit_size.div_ceil(16).saturating_mul(16));
        items.push(item);
    }
    let entries: Vec<(u8, &SubObject)> = object
        .subs
        .iter()
        .filter(|(&s, _)| s != 0)
        .map(|(&s, sub)| (s, sub))
        .collect();
    if object.kind == ObjectKind::Array {
        let contiguous = entries
            .iter()
            .enumerate()
            .all(|(i, (s, _))| usize::from(*s) == i + 1);
        let uniform = entries.windows(2).all(|p| {
            let (a, b) = (p[0].1, p[1].1);
            a.data_type == b.data_type
                && entry_bits(a) == entry_bits(b)
                && a.access == b.access
                && a.pdo == b.pdo
                && a.description == b.description
        });
        if entries.is_empty() {
            // An array without elements: the element type is not known; USINT stands in.
            items.push(Item {
                sub: 1,
                name: "Elements".to_string(),
                type_name: String::new(),
                comment: None,
                bit_size: 0,
                bit_offs: offset,
                access: Access::new(AccessType::Ro),
                pdo: PdoMapping::None,
            });
            return Struct {
                bit_size: offset,
                items,
                arr: Some(Arr {
                    base: "USINT".to_string(),
                    element_bits: 8,
                    elements: 0,
                }),
            };
        }
        if contiguous && uniform {
            if let Some((_, e)) = entries.first() {
                let bits = entry_bits(e);
                let n = u32::try_from(entries.len()).unwrap_or(255);
                let mut item = item_of(1, e, offset);
                item.name = "Elements".to_string();
                item.bit_size = bits.saturating_mul(n);
                items.push(item);
                return Struct {
                    bit_size: offset.saturating_add(bits.saturating_mul(n)),
                    items,
                    arr: Some(Arr {
                        base: entry_type_name(e),
                        element_bits: bits,
                        elements: n,
                    }),
                };
            }
        }
    }
    for (s, sub) in entries {
        let item = item_of(s, sub, offset);
        offset = offset.saturating_add(item.bit_size);
        items.push(item);
    }
    Struct {
        bit_size: offset,
        items,
        arr: None,
    }
}

fn valid_type_name(name: &str) -> bool {
    !name.is_empty()
        && name.trim() == name
        && DataType::from_esi_name(name).is_none()
        && !name.contains(['<', '>', '&'])
}

/// The structure types of a dictionary and the type name of each RECORD/ARRAY object.
struct Types {
    /// Name → structure, in the order written.
    structs: Vec<(String, Struct)>,
    by_object: HashMap<u16, usize>,
    basics: BTreeMap<String, u32>,
}

impl Types {
    fn of(dictionary: &Dictionary) -> Types {
        let mut t = Types {
            structs: Vec::new(),
            by_object: HashMap::new(),
            basics: BTreeMap::new(),
        };
        for object in dictionary.objects() {
            if !object.kind.has_subs() {
                if let Some(sub) = object.subs.get(&0) {
                    t.basics.insert(entry_type_name(sub), entry_bits(sub));
                }
                continue;
            }
            for sub in object.subs.values() {
                t.basics.insert(entry_type_name(sub), entry_bits(sub));
            }
            let def = struct_of(object);
            if let Some(arr) = &def.arr {
                t.basics.insert(arr.base.clone(), arr.element_bits);
            }
            let preferred = object
                .type_name
                .as_deref()
                .filter(|n| valid_type_name(n))
                .map_or_else(|| format!("DT{:04X}", object.index), str::to_string);
            let fallback = format!("DT{:04X}", object.index);
            let mut candidates = vec![preferred, fallback.clone()];
            candidates.extend((1..).take(256).map(|n| format!("{fallback}_{n}")));
            for name in candidates {
                if let Some(pos) = t.structs.iter().position(|(n, _)| *n == name) {
                    if t.structs[pos].1 == def {
                        t.by_object.insert(object.index, pos);
                        break;
                    }
                    continue;
                }
                let arr_name = format!("{name}ARR");
                let clash = t
                    .structs
                    .iter()
                    .any(|(n, s)| (s.arr.is_some() && format!("{n}ARR") == name) || *n == arr_name);
                if clash {
                    continue;
                }
                t.by_object.insert(object.index, t.structs.len());
                t.structs.push((name, def));
                break;
            }
        }
        t
    }

    fn name_of(&self, index: u16) -> Option<&str> {
        self.by_object
            .get(&index)
            .and_then(|&i| self.structs.get(i))
            .map(|(n, _)| n.as_str())
    }

    fn bits_of(&self, index: u16) -> u32 {
        self.by_object
            .get(&index)
            .and_then(|&i| self.structs.get(i))
            .map_or(0, |(_, s)| s.bit_size)
    }
}

fn write_dictionary(w: &mut XmlWriter, dictionary: &Dictionary, node: u8) {
    let types = Types::of(dictionary);
    w.start("Dictionary", &[]);
    w.start("DataTypes", &[]);
    for (name, bits) in &types.basics {
        w.start("DataType", &[]);
        w.text("Name", &[], name);
        w.text("BitSize", &[], &bits.to_string());
        w.end();
    }
    for (name, def) in &types.structs {
        if let Some(arr) = &def.arr {
            w.start("DataType", &[]);
            w.text("Name", &[], &format!("{name}ARR"));
            w.text("BaseType", &[], &arr.base);
            w.text(
                "BitSize",
                &[],
                &arr.element_bits.saturating_mul(arr.elements).to_string(),
            );
            w.start("ArrayInfo", &[]);
            w.text("LBound", &[], "1");
            w.text("Elements", &[], &arr.elements.to_string());
            w.end();
            w.end();
        }
        w.start("DataType", &[]);
        w.text("Name", &[], name);
        w.text("BitSize", &[], &def.bit_size.to_string());
        for item in &def.items {
            w.start("SubItem", &[]);
            let is_elements = def.arr.is_some() && item.sub != 0;
            if !is_elements {
                w.text("SubIdx", &[], &item.sub.to_string());
            }
            w.text("Name", &[], &item.name);
            if is_elements {
                w.text("Type", &[], &format!("{name}ARR"));
            } else {
                w.text("Type", &[], &item.type_name);
            }
            if let Some(c) = &item.comment {
                w.text("Comment", &[("LcId", "1033")], c);
            }
            w.text("BitSize", &[], &item.bit_size.to_string());
            w.text("BitOffs", &[], &item.bit_offs.to_string());
            write_flags(w, item.access, item.pdo);
            w.end();
        }
        w.end();
    }
    w.end();
    w.start("Objects", &[]);
    for object in dictionary.objects() {
        write_object(w, object, &types, node);
    }
    w.end();
    w.end();
}

fn info_children(w: &mut XmlWriter, sub: &SubObject, node: u8) {
    let t = sub.data_type;
    if let Some(low) = sub.low.as_ref().and_then(|v| v.encode(t).ok()) {
        w.text("MinData", &[], &hex_bytes(&low));
    }
    if let Some(high) = sub.high.as_ref().and_then(|v| v.encode(t).ok()) {
        w.text("MaxData", &[], &hex_bytes(&high));
    }
    if let Some(d) = sub
        .default
        .as_ref()
        .and_then(|d| d.resolve(node).encode(t).ok())
    {
        w.text("DefaultData", &[], &hex_bytes(&d));
    }
    if let Some(u) = sub.unit {
        w.text("Unit", &[], &format!("#x{u:08x}"));
    }
}

fn has_info(sub: &SubObject) -> bool {
    sub.low.is_some() || sub.high.is_some() || sub.default.is_some() || sub.unit.is_some()
}

fn write_object(w: &mut XmlWriter, object: &Object, types: &Types, node: u8) {
    if !object.kind.has_subs() {
        let Some(sub) = object.subs.get(&0) else {
            return;
        };
        w.start("Object", &[]);
        w.text("Index", &[], &hex16(object.index));
        w.text("Name", &[], &object.name);
        if let Some(c) = object.description.as_ref().or(sub.description.as_ref()) {
            w.text("Comment", &[("LcId", "1033")], c);
        }
        w.text("Type", &[], &entry_type_name(sub));
        w.text("BitSize", &[], &entry_bits(sub).to_string());
        if has_info(sub) {
            w.start("Info", &[]);
            info_children(w, sub, node);
            w.end();
        }
        write_flags(w, sub.access, sub.pdo);
        w.end();
        return;
    }
    let Some(type_name) = types.name_of(object.index) else {
        return;
    };
    w.start("Object", &[]);
    w.text("Index", &[], &hex16(object.index));
    w.text("Name", &[], &object.name);
    if let Some(c) = &object.description {
        w.text("Comment", &[("LcId", "1033")], c);
    }
    w.text("Type", &[], type_name);
    w.text("BitSize", &[], &types.bits_of(object.index).to_string());
    w.start("Info", &[]);
    for sub in object.subs.values() {
        w.start("SubItem", &[]);
        w.text("Name", &[], &sub.name);
        if has_info(sub) {
            w.start("Info", &[]);
            info_children(w, sub, node);
            w.end();
        } else {
            w.empty("Info", &[]);
        }
        w.end();
    }
    w.end();
    let writable = object.subs.values().any(|s| s.access.kind.writable());
    w.start("Flags", &[]);
    w.text("Access", &[], if writable { "rw" } else { "ro" });
    w.end();
    w.end();
}
