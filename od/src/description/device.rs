//! A device description: identity, dictionary, and the parts of each description format that are not
//! dictionary entries (EtherCAT sync managers, FMMUs, fixed PDOs, mailbox, DC op modes and EEPROM from ESI;
//! file and device information from EDS and XDD; commissioning values from DCF).
//!
//! Every reader produces a [`DeviceDescription`] and every writer consumes one, so any description can be
//! written in any format; what a format cannot carry is left out of its output.

use std::sync::Arc;

use crate::dict::Dictionary;

/// Who made the device and which device it is.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Identity {
    /// Vendor ID (CiA 301 0x1018:01; ESI `Vendor/Id`; EDS `VendorNumber`).
    pub vendor_id: u32,
    /// Vendor name.
    pub vendor_name: String,
    /// Product code (0x1018:02; ESI `Type@ProductCode`; EDS `ProductNumber`).
    pub product_code: u32,
    /// Revision number (0x1018:03; ESI `Type@RevisionNo`; EDS `RevisionNumber`).
    pub revision: u32,
    /// Product name (ESI `Device/Name`, EDS `ProductName`).
    pub product_name: String,
    /// The type name of the device (ESI `Device/Type` text, EDS `OrderCode`).
    pub order_code: String,
    /// The hardware version (XDD `version versionType="HW"`); empty where the description gives
    /// none (EDS and ESI have no such key).
    pub hardware_version: String,
    /// The software version (XDD `version versionType="SW"`); empty where the description gives
    /// none.
    pub software_version: String,
    /// The firmware version (XDD `version versionType="FW"`); empty where the description gives
    /// none.
    pub firmware_version: String,
}

/// Version and authorship of a description file (EDS `[FileInfo]`, XDD `ProfileHeader` and `fileName`…).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct FileInfo {
    /// File name the file gives for itself.
    pub file_name: String,
    /// File version (EDS `FileVersion`, XDD `fileVersion`).
    pub file_version: String,
    /// File revision (EDS `FileRevision`).
    pub file_revision: String,
    /// Format version (EDS `EDSVersion`, e.g. `4.0`).
    pub format_version: String,
    /// Free description.
    pub description: String,
    /// Creation time as written (`HH:MM(AM|PM)` in EDS).
    pub creation_time: String,
    /// Creation date as written (`MM-DD-YYYY` in EDS).
    pub creation_date: String,
    /// Author.
    pub created_by: String,
    /// Modification time as written.
    pub modification_time: String,
    /// Modification date as written.
    pub modification_date: String,
    /// Who last modified it.
    pub modified_by: String,
}

/// Communication capabilities of a CANopen device (EDS `[DeviceInfo]`, XDD `CANopenGeneralFeatures`
/// and `PhysicalLayer`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CanInfo {
    /// Supported bit rates in kbit/s, ascending (10, 20, 50, 125, 250, 500, 800, 1000).
    pub baud_rates: Vec<u32>,
    /// Simple boot-up master.
    pub simple_boot_up_master: bool,
    /// Simple boot-up slave.
    pub simple_boot_up_slave: bool,
    /// PDO mapping granularity in bits (0: fixed mapping, 8: byte-wise).
    pub granularity: u8,
    /// Dynamic channels supported.
    pub dynamic_channels: u8,
    /// Group messaging.
    pub group_messaging: bool,
    /// Number of RPDOs.
    pub nr_of_rx_pdo: u16,
    /// Number of TPDOs.
    pub nr_of_tx_pdo: u16,
    /// LSS supported.
    pub lss_supported: bool,
    /// Data types that may be used as dummies in PDO mappings (EDS `[DummyUsage]`): CiA 301 type indices.
    pub dummy_usage: Vec<u16>,
}

impl Default for CanInfo {
    fn default() -> CanInfo {
        CanInfo {
            baud_rates: Vec::new(),
            simple_boot_up_master: false,
            simple_boot_up_slave: true,
            granularity: 8,
            dynamic_channels: 0,
            group_messaging: false,
            nr_of_rx_pdo: 0,
            nr_of_tx_pdo: 0,
            lss_supported: false,
            dummy_usage: Vec::new(),
        }
    }
}

/// Commissioning values of one node in a network (DCF `[DeviceComissioning]`, CiA 306 §5).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Commissioning {
    /// Node-ID, 1..127; `None` when the node is unconfigured or the file does not say (a DCF without
    /// `NodeID`, or with Lely's `NodeID=0xFF` of a node LSS has yet to configure). `$NODEID` values are
    /// then resolved with 0, as in an EDS, and stay relative to the node-ID.
    pub node_id: Option<u8>,
    /// Node name.
    pub node_name: String,
    /// Bit rate in kbit/s.
    pub baud_rate: u32,
    /// Network number.
    pub net_number: u32,
    /// Network name.
    pub network_name: String,
    /// True when this node is the CANopen manager.
    pub canopen_manager: bool,
    /// LSS serial number.
    pub lss_serial_number: u32,
}

/// The description of one device: identity, dictionary and format-specific parts.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DeviceDescription {
    /// Identity.
    pub identity: Identity,
    /// File information (EDS, XDD).
    pub file_info: FileInfo,
    /// CANopen communication capabilities (EDS, XDD).
    pub can: Option<CanInfo>,
    /// Commissioning values (DCF; XDC).
    pub commissioning: Option<Commissioning>,
    /// EtherCAT parts (ESI).
    pub ethercat: Option<EthercatInfo>,
    /// The object dictionary.
    pub dictionary: Dictionary,
    /// Free comment lines (EDS `[Comments]`).
    pub comments: Vec<String>,
}

/// The EtherCAT parts of an ESI `Device` element that are not dictionary entries (ETG.2000), with the
/// slots of a modular device and the modules of its file (ETG.2001).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EthercatInfo {
    /// `GroupType`.
    pub group_type: String,
    /// `Fmmu` elements in order: `Outputs`, `Inputs`, `MBoxState`.
    pub fmmus: Vec<String>,
    /// `Sm` elements in order.
    pub sync_managers: Vec<SyncManager>,
    /// `RxPdo` elements.
    pub rx_pdos: Vec<Pdo>,
    /// `TxPdo` elements.
    pub tx_pdos: Vec<Pdo>,
    /// `Mailbox`.
    pub mailbox: Option<Mailbox>,
    /// `Dc/OpMode` elements; the first is the default.
    pub op_modes: Vec<OpMode>,
    /// `Eeprom`.
    pub eeprom: Option<Eeprom>,
    /// `Slots`: where a modular device takes its modules.
    pub slots: Option<Slots>,
    /// The modules of the file (`Descriptions/Modules/Module`), shared by every device of the file.
    pub modules: Arc<[Module]>,
    /// The root element of the file the description is a part of, which an ESI writer writes it back
    /// in: a device of an `EtherCATInfo`, of one of an `EtherCATInfoList`'s, or a module of a module
    /// catalogue (`EtherCATModule`).
    pub root: EsiRoot,
}

/// The kind of ESI file a description is a part of (ETG.2000: the root element).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum EsiRoot {
    /// `EtherCATInfo`: the description is a `Device` of a file of devices.
    #[default]
    EtherCatInfo,
    /// `EtherCATModule` (ETG.2000 module description): the description is a `Module` of a module
    /// catalogue, a file of modules without devices. Its type name, name, PDOs, mailbox and dictionary
    /// are the description's; what a module has beyond them is here.
    EtherCatModule(CatalogueModule),
    /// `EtherCATInfoList` (ETG.2000's list of `EtherCATInfo`s, as IgH's `ethercat xml` writes the
    /// slaves of a bus): the description is a `Device` of the list's `EtherCATInfo` at this place
    /// (from 0), whose vendor and modules are its own.
    EtherCatInfoList(usize),
}

impl EsiRoot {
    /// The root element's name: `EtherCATInfo`, `EtherCATModule` or `EtherCATInfoList`.
    pub fn element(&self) -> &'static str {
        match self {
            EsiRoot::EtherCatInfo => "EtherCATInfo",
            EsiRoot::EtherCatModule(_) => "EtherCATModule",
            EsiRoot::EtherCatInfoList(_) => "EtherCATInfoList",
        }
    }

    /// True for a module of a module catalogue, false for a device.
    pub fn is_module(&self) -> bool {
        matches!(self, EsiRoot::EtherCatModule(_))
    }
}

/// What a module of a module catalogue has beyond the parts of a description (ETG.2001 `ModuleType`;
/// the same fields as a [`Module`] of an `EtherCATInfo`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct CatalogueModule {
    /// `Type@ModuleIdent`: what the device reports for it (0xF050).
    pub ident: u32,
    /// `Type@ModuleClass`.
    pub class: String,
    /// `Type@ModulePdoGroup`.
    pub pdo_group: Option<u32>,
    /// `Profile/ProfileNo`.
    pub profile_no: Option<u32>,
    /// `Profile/AddInfo`.
    pub add_info: Option<u32>,
    /// `DcOpModeName`: the device's `Dc/OpMode` the module needs.
    pub dc_op_mode_name: String,
}

/// The slots of a modular device (`Device/Slots`, ETG.2001): how many modules it takes, which, and how
/// a module's PDO and object indices move from slot to slot.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Slots {
    /// `MaxSlotCount`.
    pub max_slot_count: Option<u32>,
    /// `MaxSlotGroupCount`.
    pub max_slot_group_count: Option<u32>,
    /// `SlotPdoIncrement`: added to a slot-dependent PDO index per slot.
    pub slot_pdo_increment: Option<u32>,
    /// `SlotGroupPdoIncrement`.
    pub slot_group_pdo_increment: Option<u32>,
    /// `SlotIndexIncrement`: added to a slot-dependent object index per slot.
    pub slot_index_increment: Option<u32>,
    /// `SlotGroupIndexIncrement`.
    pub slot_group_index_increment: Option<u32>,
    /// `DownloadModuleIdentList`: the master writes the configured modules' idents to 0xF030.
    pub download_module_ident_list: bool,
    /// `IdentifyModuleBy` (obsolete), as written.
    pub identify_module_by: String,
    /// `Slot`s in order.
    pub slots: Vec<Slot>,
    /// `ModulePdoGroup`s.
    pub module_pdo_groups: Vec<ModulePdoGroup>,
}

/// One slot (`Slot`): the modules it takes, named by ident or by class.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Slot {
    /// `Name` (`LcId` 1033 preferred).
    pub name: String,
    /// `SlotGroup`.
    pub slot_group: Option<u32>,
    /// `MinInstances`.
    pub min_instances: u32,
    /// `MaxInstances`.
    pub max_instances: u32,
    /// `SlotPdoIncrement` of this slot.
    pub slot_pdo_increment: Option<u32>,
    /// `SlotGroupPdoIncrement`.
    pub slot_group_pdo_increment: Option<u32>,
    /// `SlotIndexIncrement` of this slot.
    pub slot_index_increment: Option<u32>,
    /// `SlotGroupIndexIncrement`.
    pub slot_group_index_increment: Option<u32>,
    /// `TreeView` (`SLOTGROUP`, `SLOT`, `PDO`), as written.
    pub tree_view: String,
    /// `ModuleIdent`s: the modules it takes.
    pub module_idents: Vec<SlotModuleIdent>,
    /// `ModuleClass`es: the classes of modules it takes.
    pub module_classes: Vec<SlotModuleClass>,
}

/// A `Slot/ModuleIdent`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SlotModuleIdent {
    /// The module's `ModuleIdent`.
    pub ident: u32,
    /// The `Default` attribute (1: the module a new configuration puts in the slot).
    pub default: Option<u32>,
}

/// A `Slot/ModuleClass`.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SlotModuleClass {
    /// `Class`: matched against a module's `ModuleClass`.
    pub class: String,
    /// `VendorId`.
    pub vendor_id: Option<u32>,
    /// `Name` (`LcId` 1033 preferred).
    pub name: String,
}

/// A `Slots/ModulePdoGroup`: where the PDOs of the modules of one group go.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ModulePdoGroup {
    /// The element text.
    pub name: String,
    /// `Alignment`.
    pub alignment: Option<u32>,
    /// `RxPdo`: the PDO the group's output entries are gathered in.
    pub rx_pdo: Option<u16>,
    /// `TxPdo`.
    pub tx_pdo: Option<u16>,
}

/// A module of a modular device (`Descriptions/Modules/Module`, ETG.2001 `ModuleType`). Indices that
/// move with the slot say so (`index_depend`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Module {
    /// `Type@ModuleIdent`: what the device reports for it (0xF050).
    pub ident: u32,
    /// `Type@ModuleClass`.
    pub class: String,
    /// `Type@ModulePdoGroup`.
    pub pdo_group: Option<u32>,
    /// The `Type` text: the module's type name.
    pub type_name: String,
    /// `Name` (`LcId` 1033 preferred).
    pub name: String,
    /// `RxPdo`s.
    pub rx_pdos: Vec<Pdo>,
    /// `TxPdo`s.
    pub tx_pdos: Vec<Pdo>,
    /// `Mailbox`: its CoE attributes and start-up commands.
    pub mailbox: Option<Mailbox>,
    /// `Profile/ProfileNo`.
    pub profile_no: Option<u32>,
    /// `Profile/AddInfo`.
    pub add_info: Option<u32>,
    /// `Profile/Dictionary`, with the entries its PDOs map made as for a device.
    pub dictionary: Dictionary,
    /// `DcOpModeName`: the device's `Dc/OpMode` the module needs.
    pub dc_op_mode_name: String,
}

/// One sync manager (`Sm`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SyncManager {
    /// The element text: `MBoxOut`, `MBoxIn`, `Outputs`, `Inputs`.
    pub kind: String,
    /// `StartAddress`.
    pub start_address: u16,
    /// `DefaultSize`.
    pub default_size: Option<u16>,
    /// `MinSize`.
    pub min_size: Option<u16>,
    /// `MaxSize`.
    pub max_size: Option<u16>,
    /// `ControlByte`.
    pub control_byte: u8,
    /// `Enable`, a number (ETG.2000 HexDecValue): the enable byte of the SII SyncM category
    /// (ETG.1000.6 Table 23): bit 0 enabled, bit 1 fixed content, bit 2 virtual, bit 3 enabled in Op
    /// only. Files write 0 or 1, some the whole byte (`9`).
    pub enable: u8,
    /// `Virtual`: no hardware sync manager stands behind it.
    pub is_virtual: bool,
    /// `OpOnly`: enabled only in Op.
    pub op_only: bool,
    /// `Watchdog` (obsolete in ETG.2000).
    pub watchdog: bool,
}

/// Whether an index given in a module moves with the module's slot (ETG.2001: the `DependOnSlot` and
/// `DependOnSlotGroup` attributes of an `Index` or `Exclude`; the slot's `SlotIndexIncrement` or
/// `SlotPdoIncrement` is added per slot).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SlotDepend {
    /// `DependOnSlot`.
    pub slot: bool,
    /// `DependOnSlotGroup`.
    pub slot_group: bool,
}

/// A fixed or configurable PDO of an ESI (`RxPdo` / `TxPdo`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Pdo {
    /// Index of the mapping object (`#x1600`).
    pub index: u16,
    /// Whether `index` moves with the slot (in a module).
    pub index_depend: SlotDepend,
    /// Name.
    pub name: String,
    /// `Fixed` attribute.
    pub fixed: bool,
    /// `Mandatory` attribute.
    pub mandatory: bool,
    /// `Virtual` attribute: the master makes its content (DC latch times, ESC registers) rather than
    /// the device's sync manager.
    pub is_virtual: bool,
    /// `Sm` attribute: the sync manager it is assigned to.
    pub sm: Option<u8>,
    /// `Su` attribute: the sync unit.
    pub su: Option<u8>,
    /// Oversampling (`OSFac`, `OSMin`, `OSMax`, `OSIndexInc`): the default, lowest and highest number
    /// of samples, and the index increment from one sample's entries to the next's.
    pub os_factor: Option<u32>,
    /// `OSMin`.
    pub os_min: Option<u32>,
    /// `OSMax`.
    pub os_max: Option<u32>,
    /// `OSIndexInc`.
    pub os_index_inc: Option<u32>,
    /// PDOs that cannot be assigned together with this one (`Exclude`).
    pub exclude: Vec<PdoRef>,
    /// Entries in order.
    pub entries: Vec<PdoEntry>,
}

/// The index of another PDO (`Exclude`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PdoRef {
    /// Index of the PDO's mapping object.
    pub index: u16,
    /// Whether `index` moves with the slot (in a module).
    pub depend: SlotDepend,
}

impl From<u16> for PdoRef {
    fn from(index: u16) -> PdoRef {
        PdoRef {
            index,
            depend: SlotDepend::default(),
        }
    }
}

/// One entry of a PDO.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct PdoEntry {
    /// Index of the mapped object (0 for a gap).
    pub index: u16,
    /// Whether `index` moves with the slot (in a module).
    pub index_depend: SlotDepend,
    /// Sub-index.
    pub sub: u8,
    /// Length in bits.
    pub bit_len: u16,
    /// Name.
    pub name: String,
    /// `Comment`.
    pub comment: String,
    /// Type name as the ESI writes it (`UINT`).
    pub data_type: String,
    /// The `DScale` attribute of `DataType` (`+/-10`, `0-20`…): the scaling of an analog value.
    pub data_scale: String,
    /// `Fixed` attribute: the entry cannot be changed in a configurable PDO.
    pub fixed: bool,
}

/// The mailbox protocols of an ESI (`Mailbox`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Mailbox {
    /// `DataLinkLayer` attribute.
    pub data_link_layer: bool,
    /// CoE flags, when the device speaks CoE.
    pub coe: Option<CoeFlags>,
    /// True when the device speaks FoE.
    pub foe: bool,
    /// True when the device speaks EoE.
    pub eoe: bool,
    /// The `InitCmd`s of the `CoE` element.
    pub init_cmds: Vec<InitCmd>,
}

/// A CoE start-up command (`Mailbox/CoE/InitCmd`): an SDO download the master makes at the given
/// state transitions.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct InitCmd {
    /// `Transition`s (`IP`, `PS`, `SP`, `SO`, `OS`, `OP`), as written.
    pub transitions: Vec<String>,
    /// `Index`.
    pub index: u16,
    /// Whether `index` moves with the slot (in a module).
    pub index_depend: SlotDepend,
    /// `SubIndex`.
    pub sub: u8,
    /// `Data`: the bytes downloaded.
    pub data: Vec<u8>,
    /// `Data@AdaptAutomatically`.
    pub adapt_automatically: bool,
    /// `Comment`.
    pub comment: String,
    /// `Fixed` attribute.
    pub fixed: bool,
    /// `CompleteAccess` attribute.
    pub complete_access: bool,
    /// `OverwrittenByModule` attribute.
    pub overwritten_by_module: bool,
}

/// Attributes of the `Mailbox/CoE` element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CoeFlags {
    /// `SdoInfo`.
    pub sdo_info: bool,
    /// `PdoAssign`.
    pub pdo_assign: bool,
    /// `PdoConfig`.
    pub pdo_config: bool,
    /// `PdoUpload`.
    pub pdo_upload: bool,
    /// `CompleteAccess`.
    pub complete_access: bool,
    /// `SegmentedSdo` (true when absent, as ETG.2000 defines).
    pub segmented_sdo: bool,
}

/// One distributed-clock operation mode (`Dc/OpMode`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct OpMode {
    /// `Name`.
    pub name: String,
    /// `Desc`.
    pub desc: String,
    /// `AssignActivate` (0x0000 for free run / SM-synchronous, 0x0300 for SYNC0).
    pub assign_activate: u16,
    /// `CycleTimeSync0` in ns and its `Factor` attribute.
    pub cycle_time_sync0: Option<(u32, i32)>,
    /// `ShiftTimeSync0` in ns (negative: before the SYNC0 event).
    pub shift_time_sync0: Option<i32>,
    /// `CycleTimeSync1` in ns and its `Factor` attribute.
    pub cycle_time_sync1: Option<(u32, i32)>,
    /// `ShiftTimeSync1` in ns.
    pub shift_time_sync1: Option<i32>,
}

/// The `Eeprom` element.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Eeprom {
    /// `ByteSize`.
    pub byte_size: u32,
    /// `ConfigData` bytes.
    pub config_data: Vec<u8>,
    /// `BootStrap` bytes.
    pub boot_strap: Vec<u8>,
}

impl DeviceDescription {
    /// The node-ID of the commissioning values, when the description has one.
    pub fn node_id(&self) -> Option<u8> {
        self.commissioning.as_ref().and_then(|c| c.node_id)
    }

    /// Configures the description for node `node_id` (`None`: unconfigured), adding commissioning values
    /// where there are none. Every value that follows the node-ID follows it: a `$NODEID` default that is
    /// still the current value, and a current value given as `$NODEID+offset`
    /// ([`SubObject::value_plus_node_id`](crate::object::SubObject::value_plus_node_id)). `$NODEID`
    /// values of a description without a node-ID are resolved with 0.
    pub fn set_node_id(&mut self, node_id: Option<u8>) {
        let old = self.node_id().unwrap_or(0);
        let new = node_id.unwrap_or(0);
        for object in self.dictionary.objects_mut() {
            for sub in object.subs.values_mut() {
                let value = if sub.value_plus_node_id {
                    sub.parameter(old).map(|p| p.resolve(new))
                } else {
                    match &sub.default {
                        Some(d) if d.plus_node_id && !sub.value_set => {
                            let at_default = d
                                .resolve(old)
                                .encode(sub.data_type)
                                .is_ok_and(|b| b == sub.value);
                            at_default.then(|| d.resolve(new))
                        }
                        _ => None,
                    }
                };
                if let Some(bytes) = value.and_then(|v| v.encode(sub.data_type).ok()) {
                    sub.value = bytes;
                }
            }
        }
        self.commissioning
            .get_or_insert_with(Commissioning::default)
            .node_id = node_id;
    }

    /// Marks the current value of every configurable entry as set
    /// ([`SubObject::value_set`](crate::object::SubObject::value_set)), so that a DCF written from the
    /// description gives each a `ParameterValue` and a configuration tool applying the DCF
    /// (`sdo-tool apply`) writes them all. Configurable: writable (`rw`, `wo`, `rwr`, `rww`), neither a
    /// DOMAIN (an empty download into a program or data domain configures nothing) nor one of the command
    /// entries of CiA 301 and CiA 302, where a device refuses anything but a command or acts on it: 0x1003:00
    /// (0 clears the error history), 0x1010 and 0x1011 (the `save` and `load` signatures), 0x1F25 (`conf`),
    /// 0x1F51 (program control). An entry still at its `$NODEID` default gets that default for the
    /// description's node-ID, relative to the node-ID
    /// ([`SubObject::value_plus_node_id`](crate::object::SubObject::value_plus_node_id)).
    pub fn configure_writable(&mut self) {
        let node_id = self.node_id().unwrap_or(0);
        for object in self.dictionary.objects_mut() {
            let index = object.index;
            for (&sub_index, sub) in object.subs.iter_mut() {
                if sub.value_set || !configurable(index, sub_index, sub) {
                    continue;
                }
                let relative = sub
                    .default
                    .as_ref()
                    .filter(|d| d.plus_node_id)
                    .and_then(|d| {
                        let at = |id| {
                            d.resolve(id).encode(sub.data_type).ok() == Some(sub.value.clone())
                        };
                        (at(node_id) || at(0))
                            .then(|| d.resolve(node_id).encode(sub.data_type).ok())
                            .flatten()
                    });
                if let Some(bytes) = relative {
                    sub.value = bytes;
                    sub.value_plus_node_id = true;
                }
                sub.value_set = true;
            }
        }
    }

    /// Applies identity values from outside (the generator's overrides): each `Some` replaces the
    /// description's value, in the identity and in 0x1018 where the dictionary has it.
    pub fn override_identity(
        &mut self,
        vendor_id: Option<u32>,
        product_code: Option<u32>,
        revision: Option<u32>,
    ) {
        for (value, sub) in [(vendor_id, 1u8), (product_code, 2), (revision, 3)] {
            let Some(v) = value else { continue };
            match sub {
                1 => self.identity.vendor_id = v,
                2 => self.identity.product_code = v,
                _ => self.identity.revision = v,
            }
            if let Some(entry) = self
                .dictionary
                .object_mut(0x1018)
                .and_then(|o| o.subs.get_mut(&sub))
            {
                let value = crate::value::Value::Uint(v as u64);
                if let Ok(bytes) = value.encode(entry.data_type) {
                    entry.value = bytes;
                    entry.default = Some(crate::object::DefaultValue::plain(value));
                }
            }
        }
    }
}

/// True when a configuration tool may write `entry` (`index:sub`) as a setting: see
/// [`DeviceDescription::configure_writable`].
fn configurable(index: u16, sub: u8, entry: &crate::object::SubObject) -> bool {
    let command = matches!(index, 0x1010 | 0x1011 | 0x1F25 | 0x1F51) || (index, sub) == (0x1003, 0);
    entry.access.kind.writable() && entry.data_type != crate::types::DataType::Domain && !command
}
