//! Differences between two device descriptions: every part of the model — identity, file information,
//! CAN capabilities, commissioning, the EtherCAT parts (group type, FMMUs, sync managers, PDOs, mailbox,
//! DC op modes, EEPROM), the dictionary and the comments — and, between two files of several devices,
//! which devices pair with which.
//!
//! A [`Difference`] is a place in the description (a path of [`Step`]s) and a [`Change`] there: a part
//! only one side has, or a field whose values differ, each value shown as text ([`Shown`]). Everything is
//! compared on the values of the model, never on their text, so two descriptions are diff-equal exactly
//! when the model holds the same for both (reals compared bit for bit, so that NaN equals NaN).
//!
//! The comparison of each model struct destructures the struct whole: a field added to the model does not
//! compile until it is compared here. A list of parts is compared part by part, matched by a key (a PDO by
//! its index, an op mode by its name) or by position (sync managers, PDO entries, comment lines), with
//! the parts only one side has reported and, for keyed lists, a change of order.

use std::collections::{BTreeSet, HashMap};
use std::fmt;

use crate::device::{
    CanInfo, CoeFlags, Commissioning, DeviceDescription, Eeprom, EthercatInfo, FileInfo, Identity,
    InitCmd, Mailbox, Module, ModulePdoGroup, OpMode, Pdo, PdoEntry, PdoRef, Slot, SlotDepend,
    SlotModuleClass, SlotModuleIdent, Slots, SyncManager,
};
use crate::dict::Dictionary;
use crate::object::{Object, SubObject};
use crate::types::DataType;
use crate::value::Value;

/// One step of the path to a difference.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Step {
    /// A part of the description that there is one of: `identity`, `file info`, `CAN`, `mailbox`…
    Part(&'static str),
    /// One of several parts of a kind, and its key: (`RxPdo`, `0x1600`), (`Sm`, `2`), (`entry`, `1`).
    Item {
        /// The kind of part.
        kind: &'static str,
        /// Which one: its index, name or position.
        key: String,
    },
    /// A dictionary object.
    Object(u16),
    /// A sub-object of the dictionary.
    Entry(u16, u8),
}

impl fmt::Display for Step {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Step::Part(name) => f.write_str(name),
            Step::Item { kind, key } => write!(f, "{kind} {key}"),
            Step::Object(index) => write!(f, "0x{index:04X}"),
            Step::Entry(index, sub) => write!(f, "0x{index:04X}:{sub:02X}"),
        }
    }
}

/// A value as a difference shows it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Shown {
    /// Text of the description (a name, a string value): shown quoted.
    Text(String),
    /// Anything else (a number, a flag, a list, `none`): shown as it is.
    Plain(String),
}

impl Shown {
    /// The text without quotes.
    pub fn as_str(&self) -> &str {
        match self {
            Shown::Text(t) | Shown::Plain(t) => t,
        }
    }
}

impl fmt::Display for Shown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Shown::Text(t) => write!(f, "{t:?}"),
            Shown::Plain(t) => f.write_str(t),
        }
    }
}

/// What differs at a place.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Change {
    /// Only `a` has the part; its name (empty for a part that has none).
    OnlyInA(String),
    /// Only `b` has the part; its name.
    OnlyInB(String),
    /// A field both have, with different values.
    Changed {
        /// The field: `name`, `type`, `access`, `value`, `start address`, `RxPdo order`…
        field: &'static str,
        /// The value in `a`.
        a: Shown,
        /// The value in `b`.
        b: Shown,
    },
}

/// One difference between description `a` and description `b`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Difference {
    /// Where: the steps from the description down to the part (empty for a field of the description's
    /// EtherCAT parts themselves, such as the group type).
    pub path: Vec<Step>,
    /// What differs there.
    pub change: Change,
}

impl Difference {
    /// The dictionary index of a difference in the dictionary.
    pub fn index(&self) -> Option<u16> {
        match self.path.first() {
            Some(Step::Object(index) | Step::Entry(index, _)) => Some(*index),
            _ => None,
        }
    }

    /// The sub-index of a difference in a sub-object of the dictionary.
    pub fn sub(&self) -> Option<u8> {
        match self.path.first() {
            Some(Step::Entry(_, sub)) => Some(*sub),
            _ => None,
        }
    }

    /// The path as text: its steps joined by spaces.
    pub fn place(&self) -> String {
        self.path
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    }
}

impl fmt::Display for Difference {
    /// `- PLACE NAME`, `+ PLACE NAME` or `~ PLACE FIELD: A -> B`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let place = self.place();
        let join = |prefix: &str, tail: &str| {
            [prefix, place.as_str(), tail]
                .iter()
                .filter(|s| !s.is_empty())
                .copied()
                .collect::<Vec<_>>()
                .join(" ")
        };
        match &self.change {
            Change::OnlyInA(name) => f.write_str(&join("-", name)),
            Change::OnlyInB(name) => f.write_str(&join("+", name)),
            Change::Changed { field, a, b } => write!(f, "{}: {a} -> {b}", join("~", field)),
        }
    }
}

/// Every difference between dictionary `a` and dictionary `b`, in index order. Empty when the
/// dictionaries hold the same.
pub fn diff(a: &Dictionary, b: &Dictionary) -> Vec<Difference> {
    let mut out = Vec::new();
    dictionary(&mut Cx::new(&mut out), a, b);
    out
}

/// Every difference between description `a` and description `b`: identity, file information, CAN
/// capabilities, commissioning, EtherCAT parts, dictionary (in index order) and comments, in that order.
/// Empty when the model holds the same for both.
pub fn diff_devices(a: &DeviceDescription, b: &DeviceDescription) -> Vec<Difference> {
    let mut out = Vec::new();
    device(&mut Cx::new(&mut out), a, b);
    out
}

/// How a device of file `a` pairs with one of file `b`, by position in each file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pairing {
    /// The devices to compare.
    Both(usize, usize),
    /// A device of `a` that `b` does not have.
    OnlyInA(usize),
    /// A device of `b` that `a` does not have.
    OnlyInB(usize),
}

/// Pairs the devices of two files. Two files of one device each pair those two, whatever they are.
/// Otherwise devices pair by product code and revision; where several devices of either file share a
/// product code and revision (several devices with product code 0), those pair by name (type name, else
/// product name). The pairs and the devices only `a` has come in `a`'s order, then the devices only `b`
/// has in `b`'s order.
pub fn pair_devices(a: &[DeviceDescription], b: &[DeviceDescription]) -> Vec<Pairing> {
    if a.len() == 1 && b.len() == 1 {
        return vec![Pairing::Both(0, 0)];
    }
    let key = |d: &DeviceDescription| (d.identity.product_code, d.identity.revision);
    let name = |d: &DeviceDescription| {
        if d.identity.order_code.is_empty() {
            d.identity.product_name.clone()
        } else {
            d.identity.order_code.clone()
        }
    };
    let mut in_b: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (j, y) in b.iter().enumerate() {
        in_b.entry(key(y)).or_default().push(j);
    }
    let mut in_a: HashMap<(u32, u32), usize> = HashMap::new();
    for x in a {
        *in_a.entry(key(x)).or_default() += 1;
    }
    let mut used = vec![false; b.len()];
    let mut out = Vec::new();
    for (i, x) in a.iter().enumerate() {
        let same_key = in_b.get(&key(x)).map_or(&[][..], Vec::as_slice);
        let hit = if same_key.len() == 1 && in_a.get(&key(x)) == Some(&1) {
            same_key.first().copied()
        } else {
            same_key
                .iter()
                .copied()
                .find(|&j| !used[j] && name(&b[j]) == name(x))
        };
        match hit {
            Some(j) => {
                used[j] = true;
                out.push(Pairing::Both(i, j));
            }
            None => out.push(Pairing::OnlyInA(i)),
        }
    }
    out.extend((0..b.len()).filter(|&j| !used[j]).map(Pairing::OnlyInB));
    out
}

/// Where the comparison is and what it found.
struct Cx<'o> {
    path: Vec<Step>,
    out: &'o mut Vec<Difference>,
}

/// How the parts of a list are told apart.
enum Key<T> {
    /// By position, numbered from the given first number.
    Position(usize),
    /// By a key (an index, a name); parts with equal keys pair in their order. A change of the order of
    /// the parts both have is reported as `order` (`RxPdo order`).
    By {
        /// The key of a part.
        key: fn(&T) -> String,
        /// The field that reports a change of order.
        order: &'static str,
    },
}

/// A list of parts of one kind.
struct List<T> {
    /// The kind, the first word of each part's step (`RxPdo`).
    kind: &'static str,
    /// How parts pair.
    key: Key<T>,
    /// The name a part only one side has is reported with.
    name: fn(&T) -> String,
    /// Compares two paired parts.
    compare: fn(&mut Cx<'_>, &T, &T),
}

impl<'o> Cx<'o> {
    fn new(out: &'o mut Vec<Difference>) -> Cx<'o> {
        Cx {
            path: Vec::new(),
            out,
        }
    }

    fn push(&mut self, step: Option<Step>, change: Change) {
        let mut path = self.path.clone();
        path.extend(step);
        self.out.push(Difference { path, change });
    }

    /// Runs `f` one step further down.
    fn within(&mut self, step: Step, f: impl FnOnce(&mut Cx<'_>)) {
        self.path.push(step);
        f(self);
        self.path.pop();
    }

    /// Reports `field` when `differ`, showing the values with `show`; where both show the same text the
    /// values are shown as the model holds them, by `held`.
    fn report<T: ?Sized>(
        &mut self,
        field: &'static str,
        differ: bool,
        (a, b): (&T, &T),
        show: impl Fn(&T) -> Shown,
        held: impl Fn(&T) -> String,
    ) {
        if !differ {
            return;
        }
        let (mut x, mut y) = (show(a), show(b));
        if x == y {
            x = Shown::Plain(held(a));
            y = Shown::Plain(held(b));
        }
        self.push(None, Change::Changed { field, a: x, b: y });
    }

    /// Reports `field` when the values differ.
    fn field<T: PartialEq + fmt::Debug + ?Sized>(
        &mut self,
        field: &'static str,
        a: &T,
        b: &T,
        show: impl Fn(&T) -> Shown,
    ) {
        self.report(field, a != b, (a, b), show, |v| format!("{v:?}"));
    }

    /// A text field, shown quoted.
    fn text(&mut self, field: &'static str, a: &str, b: &str) {
        self.field(field, a, b, |t| Shown::Text(t.to_string()));
    }

    /// A field shown by its `Display`.
    fn plain<T: PartialEq + fmt::Debug + fmt::Display>(
        &mut self,
        field: &'static str,
        a: &T,
        b: &T,
    ) {
        self.field(field, a, b, |v| Shown::Plain(v.to_string()));
    }

    /// A part that one side may lack: `step` alone when only one side has it, compared by `f` when both do.
    fn option<T>(
        &mut self,
        step: Step,
        a: &Option<T>,
        b: &Option<T>,
        f: impl FnOnce(&mut Cx<'_>, &T, &T),
    ) {
        match (a, b) {
            (Some(x), Some(y)) => self.within(step, |cx| f(cx, x, y)),
            (Some(_), None) => self.push(Some(step), Change::OnlyInA(String::new())),
            (None, Some(_)) => self.push(Some(step), Change::OnlyInB(String::new())),
            (None, None) => {}
        }
    }

    /// Pairs the parts of two lists and compares each pair; reports the parts only one side has and, for
    /// keyed parts, a change of the order of the parts both have.
    fn list<T>(&mut self, list: List<T>, a: &[T], b: &[T]) {
        let (ka, kb) = (list.key.of(a), list.key.of(b));
        let in_b: HashMap<&(String, usize), usize> =
            kb.iter().enumerate().map(|(j, k)| (k, j)).collect();
        let label = |(key, n): &(String, usize)| match n {
            1 => key.clone(),
            n => format!("{key} #{n}"),
        };
        let step = |k: &(String, usize)| Step::Item {
            kind: list.kind,
            key: label(k),
        };
        let mut paired = vec![false; b.len()];
        let mut order = Vec::new();
        for (i, k) in ka.iter().enumerate() {
            match in_b.get(k) {
                Some(&j) => {
                    paired[j] = true;
                    order.push(j);
                    self.within(step(k), |cx| (list.compare)(cx, &a[i], &b[j]));
                }
                None => self.push(Some(step(k)), Change::OnlyInA((list.name)(&a[i]))),
            }
        }
        for (j, k) in kb.iter().enumerate() {
            if !paired[j] {
                self.push(Some(step(k)), Change::OnlyInB((list.name)(&b[j])));
            }
        }
        let Key::By { order: field, .. } = list.key else {
            return;
        };
        if order.windows(2).any(|w| w[0] > w[1]) {
            let keys = |js: &[usize]| {
                let shown: Vec<String> = js.iter().map(|&j| label(&kb[j])).collect();
                Shown::Plain(shown.join(", "))
            };
            let a = keys(&order);
            order.sort_unstable();
            let b = keys(&order);
            self.push(None, Change::Changed { field, a, b });
        }
    }
}

impl<T> Key<T> {
    /// The key of each of `items` and its occurrence among equal keys (1 for the first).
    fn of(&self, items: &[T]) -> Vec<(String, usize)> {
        let mut seen: HashMap<String, usize> = HashMap::new();
        items
            .iter()
            .enumerate()
            .map(|(i, item)| match self {
                Key::Position(first) => ((first + i).to_string(), 1),
                Key::By { key, .. } => {
                    let k = key(item);
                    let n = seen.entry(k.clone()).or_default();
                    *n += 1;
                    (k, *n)
                }
            })
            .collect()
    }
}

fn device(cx: &mut Cx<'_>, a: &DeviceDescription, b: &DeviceDescription) {
    let DeviceDescription {
        identity,
        file_info,
        can,
        commissioning: commissioned,
        ethercat: ecat,
        dictionary: dict,
        comments,
    } = a;
    cx.within(Step::Part("identity"), |cx| {
        self::identity(cx, identity, &b.identity)
    });
    cx.within(Step::Part("file info"), |cx| {
        self::file_info(cx, file_info, &b.file_info)
    });
    cx.option(Step::Part("CAN"), can, &b.can, can_info);
    cx.option(
        Step::Part("commissioning"),
        commissioned,
        &b.commissioning,
        commissioning,
    );
    match (ecat, &b.ethercat) {
        // The EtherCAT parts are named by their own kinds (`RxPdo 0x1600`, `Sm 2`), not under `EtherCAT`.
        (Some(x), Some(y)) => ethercat(cx, x, y),
        (x, y) => cx.option(Step::Part("EtherCAT"), x, y, |_, _, _| {}),
    }
    dictionary(cx, dict, &b.dictionary);
    cx.list(
        List {
            kind: "comment",
            key: Key::Position(1),
            name: |line: &String| line.clone(),
            compare: |cx, x: &String, y: &String| cx.text("text", x, y),
        },
        comments,
        &b.comments,
    );
}

fn hex8(v: &u32) -> Shown {
    Shown::Plain(format!("0x{v:08X}"))
}

fn hex4(v: &u16) -> Shown {
    Shown::Plain(format!("0x{v:04X}"))
}

fn hex2(v: &u8) -> Shown {
    Shown::Plain(format!("0x{v:02X}"))
}

fn or_none<T>(v: &Option<T>, show: impl Fn(&T) -> String) -> String {
    v.as_ref().map_or_else(|| "none".to_string(), show)
}

fn joined<T>(items: &[T], show: impl Fn(&T) -> String) -> Shown {
    if items.is_empty() {
        return Shown::Plain("none".into());
    }
    Shown::Plain(items.iter().map(show).collect::<Vec<_>>().join(", "))
}

fn bytes_text(bytes: &[u8]) -> String {
    if bytes.is_empty() {
        return "(empty)".into();
    }
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn identity(cx: &mut Cx<'_>, a: &Identity, b: &Identity) {
    let Identity {
        vendor_id,
        vendor_name,
        product_code,
        revision,
        product_name,
        order_code,
    } = a;
    cx.field("vendor ID", vendor_id, &b.vendor_id, hex8);
    cx.text("vendor name", vendor_name, &b.vendor_name);
    cx.field("product code", product_code, &b.product_code, hex8);
    cx.field("revision", revision, &b.revision, hex8);
    cx.text("product name", product_name, &b.product_name);
    cx.text("order code", order_code, &b.order_code);
}

fn file_info(cx: &mut Cx<'_>, a: &FileInfo, b: &FileInfo) {
    let FileInfo {
        file_name,
        file_version,
        file_revision,
        format_version,
        description,
        creation_time,
        creation_date,
        created_by,
        modification_time,
        modification_date,
        modified_by,
    } = a;
    cx.text("file name", file_name, &b.file_name);
    cx.text("file version", file_version, &b.file_version);
    cx.text("file revision", file_revision, &b.file_revision);
    cx.text("format version", format_version, &b.format_version);
    cx.text("description", description, &b.description);
    cx.text("creation time", creation_time, &b.creation_time);
    cx.text("creation date", creation_date, &b.creation_date);
    cx.text("created by", created_by, &b.created_by);
    cx.text("modification time", modification_time, &b.modification_time);
    cx.text("modification date", modification_date, &b.modification_date);
    cx.text("modified by", modified_by, &b.modified_by);
}

fn can_info(cx: &mut Cx<'_>, a: &CanInfo, b: &CanInfo) {
    let CanInfo {
        baud_rates,
        simple_boot_up_master,
        simple_boot_up_slave,
        granularity,
        dynamic_channels,
        group_messaging,
        nr_of_rx_pdo,
        nr_of_tx_pdo,
        lss_supported,
        dummy_usage,
    } = a;
    cx.field("bit rates", baud_rates, &b.baud_rates, |v| {
        joined(v, |r| format!("{r} kbit/s"))
    });
    cx.plain(
        "simple boot-up master",
        simple_boot_up_master,
        &b.simple_boot_up_master,
    );
    cx.plain(
        "simple boot-up slave",
        simple_boot_up_slave,
        &b.simple_boot_up_slave,
    );
    cx.plain("granularity", granularity, &b.granularity);
    cx.plain("dynamic channels", dynamic_channels, &b.dynamic_channels);
    cx.plain("group messaging", group_messaging, &b.group_messaging);
    cx.plain("RPDOs", nr_of_rx_pdo, &b.nr_of_rx_pdo);
    cx.plain("TPDOs", nr_of_tx_pdo, &b.nr_of_tx_pdo);
    cx.plain("LSS", lss_supported, &b.lss_supported);
    cx.field("dummy usage", dummy_usage, &b.dummy_usage, |v| {
        joined(v, |t| format!("0x{t:04X}"))
    });
}

fn commissioning(cx: &mut Cx<'_>, a: &Commissioning, b: &Commissioning) {
    let Commissioning {
        node_id,
        node_name,
        baud_rate,
        net_number,
        network_name,
        canopen_manager,
        lss_serial_number,
    } = a;
    cx.field("node ID", node_id, &b.node_id, |v| {
        Shown::Plain(or_none(v, u8::to_string))
    });
    cx.text("node name", node_name, &b.node_name);
    cx.field("bit rate", baud_rate, &b.baud_rate, |r| {
        Shown::Plain(format!("{r} kbit/s"))
    });
    cx.plain("net number", net_number, &b.net_number);
    cx.text("network name", network_name, &b.network_name);
    cx.plain("CANopen manager", canopen_manager, &b.canopen_manager);
    cx.field(
        "LSS serial number",
        lss_serial_number,
        &b.lss_serial_number,
        hex8,
    );
}

/// The EtherCAT parts. A new list of parts is one more `cx.list` here with a compare function of its
/// own, as the PDOs and modules have.
fn ethercat(cx: &mut Cx<'_>, a: &EthercatInfo, b: &EthercatInfo) {
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
    } = a;
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

fn dictionary(cx: &mut Cx<'_>, a: &Dictionary, b: &Dictionary) {
    let indices: BTreeSet<u16> = a.objects().chain(b.objects()).map(|o| o.index).collect();
    for index in indices {
        match (a.object(index), b.object(index)) {
            (Some(x), Some(y)) => object(cx, x, y),
            (Some(x), None) => cx.push(Some(Step::Object(index)), Change::OnlyInA(x.name.clone())),
            (None, Some(y)) => cx.push(Some(Step::Object(index)), Change::OnlyInB(y.name.clone())),
            (None, None) => {}
        }
    }
}

fn object(cx: &mut Cx<'_>, a: &Object, b: &Object) {
    let Object {
        index,
        name,
        description,
        kind,
        type_name,
        subs,
    } = a;
    let index = *index;
    let text = |v: &Option<String>| match v {
        Some(t) => Shown::Text(t.clone()),
        None => Shown::Plain("none".into()),
    };
    cx.within(Step::Object(index), |cx| {
        cx.text("name", name, &b.name);
        cx.field("description", description, &b.description, text);
        cx.plain("object code", kind, &b.kind);
        cx.field("type name", type_name, &b.type_name, text);
    });
    let all: BTreeSet<u8> = subs.keys().chain(b.subs.keys()).copied().collect();
    for s in all {
        let step = Step::Entry(index, s);
        match (subs.get(&s), b.subs.get(&s)) {
            (Some(x), Some(y)) => cx.within(step, |cx| sub_object(cx, x, y)),
            (Some(x), None) => cx.push(Some(step), Change::OnlyInA(x.name.clone())),
            (None, Some(y)) => cx.push(Some(step), Change::OnlyInB(y.name.clone())),
            (None, None) => {}
        }
    }
}

fn sub_object(cx: &mut Cx<'_>, a: &SubObject, b: &SubObject) {
    let SubObject {
        name,
        description,
        data_type,
        bit_size,
        access,
        pdo,
        default,
        low,
        high,
        value,
        value_set,
        value_plus_node_id,
    } = a;
    cx.text("name", name, &b.name);
    cx.field("description", description, &b.description, |v| match v {
        Some(t) => Shown::Text(t.clone()),
        None => Shown::Plain("none".into()),
    });
    cx.plain("type", data_type, &b.data_type);
    // A fixed-size type's size is the type's: a change of it is the change of type already reported.
    let natural = |s: &SubObject| s.bit_size == s.data_type.bit_size();
    if !(natural(a) && natural(b)) {
        cx.field("size", bit_size, &b.bit_size, |v| {
            Shown::Plain(v.map_or_else(|| "unbounded".into(), |bits| format!("{bits} bits")))
        });
    }
    cx.field("access", access, &b.access, |acc| {
        let mut t = acc.kind.to_string();
        if let Some(r) = acc.read_states {
            t.push_str(&format!(" read:{r}"));
        }
        if let Some(w) = acc.write_states {
            t.push_str(&format!(" write:{w}"));
        }
        Shown::Plain(t)
    });
    cx.field("PDO mapping", pdo, &b.pdo, |p| {
        Shown::Plain(format!("{p:?}"))
    });
    let (ta, tb) = (*data_type, b.data_type);
    let same_default = match (default, &b.default) {
        (Some(x), Some(y)) => x.plus_node_id == y.plus_node_id && same_value(&x.value, &y.value),
        (x, y) => x.is_none() && y.is_none(),
    };
    cx.report(
        "default",
        !same_default,
        (&(ta, default), &(tb, &b.default)),
        |(t, d)| match d {
            None => Shown::Plain("none".into()),
            Some(d) if d.plus_node_id => Shown::Plain(format!("$NODEID+{}", d.value.to_text(*t))),
            Some(d) => show_value(*t, &d.value),
        },
        |(_, d)| {
            or_none(d, |d| {
                let node = if d.plus_node_id { "$NODEID+" } else { "" };
                format!("{node}{}", held(&d.value))
            })
        },
    );
    for (field, x, y) in [("low limit", low, &b.low), ("high limit", high, &b.high)] {
        let same = match (x, y) {
            (Some(x), Some(y)) => same_value(x, y),
            (x, y) => x.is_none() && y.is_none(),
        };
        cx.report(
            field,
            !same,
            (&(ta, x), &(tb, y)),
            |(t, v)| match v {
                None => Shown::Plain("none".into()),
                Some(v) => show_value(*t, v),
            },
            |(_, v)| or_none(v, held),
        );
    }
    cx.report(
        "value",
        value != &b.value,
        (&(ta, value), &(tb, &b.value)),
        |(t, v)| show_bytes(*t, v),
        |(_, v)| bytes_text(v),
    );
    let yes_no = |set: &bool| Shown::Plain(if *set { "yes" } else { "no" }.into());
    cx.field("value set", value_set, &b.value_set, yes_no);
    cx.field(
        "value relative to the node-ID",
        value_plus_node_id,
        &b.value_plus_node_id,
        yes_no,
    );
}

/// A value as the model holds it, reals by their bits.
fn held(v: &Value) -> String {
    match v {
        Value::Real32(x) => format!("Real32(0x{:08X})", x.to_bits()),
        Value::Real64(x) => format!("Real64(0x{:016X})", x.to_bits()),
        other => format!("{other:?}"),
    }
}

/// True when two values are the same, reals compared bit for bit.
fn same_value(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Real32(x), Value::Real32(y)) => x.to_bits() == y.to_bits(),
        (Value::Real64(x), Value::Real64(y)) => x.to_bits() == y.to_bits(),
        _ => a == b,
    }
}

/// A value as its entry's type writes it: strings quoted, numbers as numbers, byte strings as bytes.
fn show_value(t: DataType, v: &Value) -> Shown {
    match v {
        Value::String(s) => Shown::Text(s.clone()),
        Value::Unicode(u) => Shown::Text(String::from_utf16_lossy(u)),
        Value::Bytes(b) => Shown::Plain(bytes_text(b)),
        other => Shown::Plain(other.to_text(t)),
    }
}

/// The current value's bytes as a value of its entry's type, or as bytes when they are no value of it.
fn show_bytes(t: DataType, bytes: &[u8]) -> Shown {
    match Value::decode(t, bytes) {
        Ok(v) => show_value(t, &v),
        Err(_) => Shown::Plain(format!("{} (not a {t})", bytes_text(bytes))),
    }
}

#[cfg(test)]
mod tests;
