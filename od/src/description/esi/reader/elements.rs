//! What each known element of an ESI means: its attributes when it starts, its text when it ends, into
//! the raw records of the current device (or the file's vendor).
//!
//! `on_start` and `on_end` pick the element's family by its path below the device element; one
//! function per family reads it: the device's identity (`Type`, `Name`, `Profile` numbers), `Slots`,
//! the dictionary's data types and objects, `Sm` and `Fmmu`, the PDOs, `Mailbox`, `Dc` and `Eeprom`.

use super::{
    clip, At, Ctx, EntryAt, Parser, RawDataType, RawDevice, RawFlags, RawInfo, RawObject,
    RawSubItem, Tag,
};
use crate::device::{
    CoeFlags, Eeprom, InitCmd, Mailbox, ModulePdoGroup, OpMode, Pdo, PdoEntry, PdoRef, Slot,
    SlotModuleClass, SlotModuleIdent, Slots, SyncManager,
};
use crate::error::ParseError;
use crate::object::EcatStates;
use crate::xml::cursor::Element;

use super::fields::{enable, flag, init_cmd_of, pdo_of, read_flag, read_info, slot_depend};

/// An element's attributes: name, value and the value's offset.
type Attrs = [(Vec<u8>, String, usize)];

/// The `ReadRestrictions` and `WriteRestrictions` of an `Access` element.
type Restrictions = (Option<EcatStates>, Option<EcatStates>);

impl Parser<'_> {
    pub(super) fn on_start(
        &mut self,
        stack: &[Tag],
        tag: Tag,
        e: &Element,
    ) -> Result<(), ParseError> {
        let offset = e.offset();
        if matches!(tag, Tag::Name | Tag::Comment) {
            self.lcid = None;
            for (k, v, at) in self.attrs(e)? {
                if k == b"LcId" {
                    self.lcid = Some(self.ctx.number(&v, at, "the LcId attribute")?);
                }
            }
        }
        let Some(depth) = self.device_depth else {
            return self.start_outside_device(stack, e, offset);
        };
        let rel = stack.get(depth + 1..).unwrap_or_default();
        let ctx = self.ctx;
        let attrs = self.attrs(e)?;
        let Some(dev) = self.device.as_mut() else {
            return Ok(());
        };
        match rel {
            [Tag::Type] => type_start(ctx, dev, &attrs),
            // Any `Flags/Access`, wherever it is.
            [.., Tag::Flags, Tag::Access] => {
                self.restrictions = access_start(ctx, &attrs)?;
                Ok(())
            }
            [Tag::Slots, rest @ ..] => slots_start(ctx, dev, rest, &attrs),
            [Tag::Profile, Tag::Dictionary, rest @ ..] => {
                dictionary_start(dev, rest, offset);
                Ok(())
            }
            [Tag::Sm] => sm_start(ctx, dev, &attrs),
            [Tag::RxPdo | Tag::TxPdo, ..] => pdo_start(ctx, dev, rel, &attrs, offset),
            [Tag::Mailbox, rest @ ..] => mailbox_start(ctx, dev, rest, &attrs),
            [Tag::Dc, rest @ ..] => dc_start(ctx, dev, rest, &attrs),
            [Tag::Eeprom] => {
                dev.ecat.eeprom = Some(Eeprom::default());
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// An element outside any device: the vendor's file version, or the start of a device or module.
    fn start_outside_device(
        &mut self,
        stack: &[Tag],
        e: &Element,
        offset: usize,
    ) -> Result<(), ParseError> {
        let device = match stack {
            [Tag::EtherCATInfo | Tag::EtherCATModule, Tag::Vendor] => {
                for (k, v, _) in self.attrs(e)? {
                    if k == b"FileVersion" {
                        self.file_version = v.trim().to_string();
                    }
                }
                return Ok(());
            }
            [Tag::EtherCATInfo, Tag::Descriptions, Tag::Devices, Tag::Device] => RawDevice {
                offset,
                ..RawDevice::default()
            },
            [Tag::EtherCATModule, Tag::Modules, Tag::Module] => RawDevice {
                offset,
                in_catalogue: true,
                ..RawDevice::default()
            },
            [Tag::EtherCATInfo, Tag::Descriptions, Tag::Modules, Tag::Module] => RawDevice {
                offset,
                is_module: true,
                ..RawDevice::default()
            },
            _ => return Ok(()),
        };
        self.device_depth = Some(stack.len() - 1);
        self.device = Some(device);
        Ok(())
    }

    pub(super) fn on_end(
        &mut self,
        stack: &[Tag],
        tag: Tag,
        text: &str,
        at: usize,
    ) -> Result<(), ParseError> {
        let lcid = if matches!(tag, Tag::Name | Tag::Comment) {
            self.lcid.take()
        } else {
            None
        };
        let ctx = self.ctx;
        let Some(depth) = self.device_depth else {
            return self.end_outside_device(stack, text, at, lcid);
        };
        let rel = stack.get(depth + 1..).unwrap_or_default();
        let restrictions = self.restrictions;
        let Some(dev) = self.device.as_mut() else {
            return Ok(());
        };
        match rel {
            [Tag::Type] => dev.order_code = text.to_string(),
            [Tag::Name] => dev.name.offer(lcid, text),
            [Tag::GroupType] => dev.group_type = text.to_string(),
            [Tag::DcOpModeName] => dev.dc_op_mode_name = text.to_string(),
            // Kept for modules; a device's profile number is not kept.
            [Tag::Profile, f @ (Tag::ProfileNo | Tag::AddInfo)]
                if dev.is_module || dev.in_catalogue =>
            {
                profile_number_end(ctx, dev, *f, text, at)
            }
            [Tag::Slots, rest @ ..] => return slots_end(ctx, dev, rest, text, at, lcid),
            [Tag::Mailbox, Tag::CoE, Tag::InitCmd, f] => {
                return init_cmd_end(ctx, dev, *f, text, at)
            }
            [Tag::Profile, Tag::Dictionary, Tag::DataTypes, Tag::DataType, rest @ ..] => {
                let end = TextAt {
                    ctx,
                    text,
                    at,
                    lcid,
                };
                return data_type_end(end, dev, rest, restrictions);
            }
            [Tag::Profile, Tag::Dictionary, Tag::Objects, Tag::Object, rest @ ..] => {
                let end = TextAt {
                    ctx,
                    text,
                    at,
                    lcid,
                };
                return object_end(end, dev, rest, restrictions);
            }
            [Tag::Fmmu] => dev.ecat.fmmus.push(text.to_string()),
            [Tag::Sm] => {
                if let Some(sm) = dev.ecat.sync_managers.last_mut() {
                    sm.kind = text.to_string();
                }
            }
            [Tag::RxPdo | Tag::TxPdo, ..] => return pdo_end(ctx, dev, rel, text, at, lcid),
            [Tag::Dc, Tag::OpMode, f] => return op_mode_end(ctx, dev, tag, *f, text, at),
            [Tag::Eeprom, f] => return eeprom_end(ctx, dev, *f, text, at),
            _ => {}
        }
        Ok(())
    }

    /// The text of an element outside any device: the vendor's id and name.
    fn end_outside_device(
        &mut self,
        stack: &[Tag],
        text: &str,
        at: usize,
        lcid: Option<u32>,
    ) -> Result<(), ParseError> {
        match stack {
            [Tag::EtherCATInfo | Tag::EtherCATModule, Tag::Vendor, Tag::Id] => {
                self.vendor_id = self.ctx.number(text, at, "<Vendor>/<Id>")?;
            }
            [Tag::EtherCATInfo | Tag::EtherCATModule, Tag::Vendor, Tag::Name] => {
                self.vendor_name.offer(lcid, text)
            }
            _ => {}
        }
        Ok(())
    }
}

/// An element's text where it ends: the document, the text, its offset and its `LcId`.
#[derive(Clone, Copy)]
struct TextAt<'a> {
    ctx: Ctx<'a>,
    text: &'a str,
    at: usize,
    lcid: Option<u32>,
}

// Where elements start: their attributes.

/// `Type`: the device's product code, revision and, for a module, its ident, class and PDO group.
fn type_start(ctx: Ctx, dev: &mut RawDevice, attrs: &Attrs) -> Result<(), ParseError> {
    for (k, v, at) in attrs {
        match k.as_slice() {
            b"ProductCode" => dev.product_code = ctx.number(v, *at, "the ProductCode attribute")?,
            b"RevisionNo" => dev.revision = ctx.number(v, *at, "the RevisionNo attribute")?,
            b"ModuleIdent" => dev.module_ident = ctx.number(v, *at, "the ModuleIdent attribute")?,
            b"ModuleClass" => dev.module_class = v.clone(),
            b"ModulePdoGroup" => {
                dev.module_pdo_group = Some(ctx.number(v, *at, "the ModulePdoGroup attribute")?)
            }
            _ => {}
        }
    }
    Ok(())
}

/// `Access` of `Flags`: the EtherCAT states an entry is read or written in.
fn access_start(ctx: Ctx, attrs: &Attrs) -> Result<Restrictions, ParseError> {
    let mut r = (None, None);
    for (k, v, at) in attrs {
        let which = match k.as_slice() {
            b"ReadRestrictions" => &mut r.0,
            b"WriteRestrictions" => &mut r.1,
            _ => continue,
        };
        *which = Some(EcatStates::parse(v).ok_or_else(|| {
            ctx.err(
                *at,
                format!(
                    "expected EtherCAT states like PreOp_SafeOp_Op in the {} attribute, found `{}`",
                    String::from_utf8_lossy(k),
                    clip(v)
                ),
            )
        })?);
    }
    Ok(r)
}

/// `Slots` and what is in it (`rest`, the path below it).
fn slots_start(
    ctx: Ctx,
    dev: &mut RawDevice,
    rest: &[Tag],
    attrs: &Attrs,
) -> Result<(), ParseError> {
    match rest {
        [] => dev.ecat.slots = Some(slots_attributes(ctx, attrs)?),
        [Tag::Slot] => {
            let slot = slot_attributes(ctx, attrs)?;
            if let Some(s) = dev.ecat.slots.as_mut() {
                s.slots.push(slot);
            }
        }
        [Tag::Slot, Tag::ModuleIdent] => {
            let mut ident = SlotModuleIdent::default();
            for (k, v, at) in attrs {
                if k == b"Default" {
                    ident.default =
                        Some(ctx.number(v, *at, "the Default attribute of <ModuleIdent>")?);
                }
            }
            if let Some(slot) = dev.ecat.slots.as_mut().and_then(|s| s.slots.last_mut()) {
                slot.module_idents.push(ident);
            }
        }
        [Tag::Slot, Tag::ModuleClass] => {
            if let Some(slot) = dev.ecat.slots.as_mut().and_then(|s| s.slots.last_mut()) {
                slot.module_classes.push(SlotModuleClass::default());
            }
        }
        [Tag::ModulePdoGroup] => {
            let mut group = ModulePdoGroup::default();
            for (k, v, at) in attrs {
                let what = format!(
                    "the {} attribute of <ModulePdoGroup>",
                    String::from_utf8_lossy(k)
                );
                match k.as_slice() {
                    b"Alignment" => group.alignment = Some(ctx.number(v, *at, &what)?),
                    b"RxPdo" => group.rx_pdo = Some(ctx.number(v, *at, &what)?),
                    b"TxPdo" => group.tx_pdo = Some(ctx.number(v, *at, &what)?),
                    _ => {}
                }
            }
            if let Some(s) = dev.ecat.slots.as_mut() {
                s.module_pdo_groups.push(group);
            }
        }
        _ => {}
    }
    Ok(())
}

/// The attributes of `Slots`.
fn slots_attributes(ctx: Ctx, attrs: &Attrs) -> Result<Slots, ParseError> {
    let mut slots = Slots::default();
    for (k, v, at) in attrs {
        let what = format!("the {} attribute of <Slots>", String::from_utf8_lossy(k));
        let field = match k.as_slice() {
            b"MaxSlotCount" => &mut slots.max_slot_count,
            b"MaxSlotGroupCount" => &mut slots.max_slot_group_count,
            b"SlotPdoIncrement" => &mut slots.slot_pdo_increment,
            b"SlotGroupPdoIncrement" => &mut slots.slot_group_pdo_increment,
            b"SlotIndexIncrement" => &mut slots.slot_index_increment,
            b"SlotGroupIndexIncrement" => &mut slots.slot_group_index_increment,
            b"DownloadModuleIdentList" => {
                slots.download_module_ident_list = flag(ctx, v, *at, &what)?;
                continue;
            }
            b"IdentifyModuleBy" => {
                slots.identify_module_by = v.clone();
                continue;
            }
            _ => continue,
        };
        *field = Some(ctx.number(v, *at, &what)?);
    }
    Ok(slots)
}

/// The attributes of a `Slot`.
fn slot_attributes(ctx: Ctx, attrs: &Attrs) -> Result<Slot, ParseError> {
    let mut slot = Slot::default();
    for (k, v, at) in attrs {
        let what = format!("the {} attribute of <Slot>", String::from_utf8_lossy(k));
        let field = match k.as_slice() {
            b"MinInstances" => {
                slot.min_instances = ctx.number(v, *at, &what)?;
                continue;
            }
            b"MaxInstances" => {
                slot.max_instances = ctx.number(v, *at, &what)?;
                continue;
            }
            b"TreeView" => {
                slot.tree_view = v.clone();
                continue;
            }
            b"SlotGroup" => &mut slot.slot_group,
            b"SlotPdoIncrement" => &mut slot.slot_pdo_increment,
            b"SlotGroupPdoIncrement" => &mut slot.slot_group_pdo_increment,
            b"SlotIndexIncrement" => &mut slot.slot_index_increment,
            b"SlotGroupIndexIncrement" => &mut slot.slot_group_index_increment,
            _ => continue,
        };
        *field = Some(ctx.number(v, *at, &what)?);
    }
    Ok(slot)
}

/// `Profile/Dictionary` and the data types and objects in it (`rest`, the path below it).
fn dictionary_start(dev: &mut RawDevice, rest: &[Tag], offset: usize) {
    match rest {
        [] => dev.has_dictionary = true,
        [Tag::DataTypes, Tag::DataType] => dev.data_types.push(RawDataType::default()),
        [Tag::DataTypes, Tag::DataType, Tag::SubItem] => {
            if let Some(dt) = dev.data_types.last_mut() {
                dt.subitems.push(RawSubItem {
                    offset,
                    ..RawSubItem::default()
                });
            }
        }
        [Tag::DataTypes, Tag::DataType, Tag::ArrayInfo] => {
            if let Some(dt) = dev.data_types.last_mut() {
                dt.arrays.push((None, None));
            }
        }
        [Tag::DataTypes, Tag::DataType, Tag::SubItem, Tag::Flags] => {
            if let Some(si) = dev
                .data_types
                .last_mut()
                .and_then(|d| d.subitems.last_mut())
            {
                si.flags.get_or_insert_with(RawFlags::default);
            }
        }
        [Tag::Objects, Tag::Object] => dev.objects.push(RawObject {
            offset,
            ..RawObject::default()
        }),
        [Tag::Objects, Tag::Object, Tag::Flags] => {
            if let Some(o) = dev.objects.last_mut() {
                o.flags.get_or_insert_with(RawFlags::default);
            }
        }
        [Tag::Objects, Tag::Object, Tag::Info, Tag::SubItem] => {
            if let Some(o) = dev.objects.last_mut() {
                o.sub_infos
                    .push((String::new(), RawInfo::default(), offset));
            }
        }
        _ => {}
    }
}

/// `Sm`: a SyncManager.
fn sm_start(ctx: Ctx, dev: &mut RawDevice, attrs: &Attrs) -> Result<(), ParseError> {
    let mut sm = SyncManager::default();
    for (k, v, at) in attrs {
        let what = format!("the {} attribute of <Sm>", String::from_utf8_lossy(k));
        match k.as_slice() {
            b"StartAddress" => sm.start_address = ctx.number(v, *at, &what)?,
            b"DefaultSize" => sm.default_size = Some(ctx.number(v, *at, &what)?),
            b"MinSize" => sm.min_size = Some(ctx.number(v, *at, &what)?),
            b"MaxSize" => sm.max_size = Some(ctx.number(v, *at, &what)?),
            b"ControlByte" => sm.control_byte = ctx.number(v, *at, &what)?,
            b"Enable" => sm.enable = enable(ctx, v, *at, &what)?,
            b"Virtual" => sm.is_virtual = flag(ctx, v, *at, &what)?,
            b"OpOnly" => sm.op_only = flag(ctx, v, *at, &what)?,
            b"Watchdog" => sm.watchdog = flag(ctx, v, *at, &what)?,
            _ => {}
        }
    }
    dev.ecat.sync_managers.push(sm);
    Ok(())
}

/// An `RxPdo` or `TxPdo` and what is in it (`rel`, the path from the PDO element).
fn pdo_start(
    ctx: Ctx,
    dev: &mut RawDevice,
    rel: &[Tag],
    attrs: &Attrs,
    offset: usize,
) -> Result<(), ParseError> {
    match rel {
        [pdo] => return pdo_element_start(ctx, dev, *pdo, attrs, offset),
        [_, ..] if dev.in_ref_pdo => {}
        [pdo, Tag::Index] => {
            let depend = slot_depend(ctx, attrs)?;
            if let Some(p) = pdo_of(dev, *pdo) {
                p.index_depend = depend;
            }
        }
        [pdo, Tag::Exclude] => {
            let depend = slot_depend(ctx, attrs)?;
            if let Some(p) = pdo_of(dev, *pdo) {
                p.exclude.push(PdoRef { index: 0, depend });
            }
        }
        [pdo, Tag::Entry] => return pdo_entry_start(ctx, dev, *pdo, attrs, offset),
        [pdo, Tag::Entry, Tag::Index] => {
            let depend = slot_depend(ctx, attrs)?;
            if let Some(e) = pdo_of(dev, *pdo).and_then(|p| p.entries.last_mut()) {
                e.index_depend = depend;
            }
        }
        [pdo, Tag::Entry, Tag::DataType] => {
            if let Some((_, v, _)) = attrs.iter().find(|(k, _, _)| k == b"DScale") {
                if let Some(e) = pdo_of(dev, *pdo).and_then(|p| p.entries.last_mut()) {
                    e.data_scale = v.clone();
                }
            }
        }
        _ => {}
    }
    Ok(())
}

/// The `RxPdo` or `TxPdo` element itself (`tag`): its attributes, or a reference to a template.
fn pdo_element_start(
    ctx: Ctx,
    dev: &mut RawDevice,
    tag: Tag,
    attrs: &Attrs,
    offset: usize,
) -> Result<(), ParseError> {
    if let Some((_, name, _)) = attrs.iter().find(|(k, _, _)| k == b"Ref") {
        // The obsolete Beckhoff form: a PDO of the file's `Descriptions/Pdos` templates.
        ctx.warn(
            offset,
            format!(
                "<{} Ref=\"{}\"> refers to a PDO template of the obsolete Descriptions/Pdos list, which is not read; the PDO is left out",
                tag.name(),
                clip(name)
            ),
        );
        dev.in_ref_pdo = true;
        return Ok(());
    }
    let mut pdo = Pdo::default();
    for (k, v, at) in attrs {
        let what = format!(
            "the {} attribute of <{}>",
            String::from_utf8_lossy(k),
            tag.name()
        );
        match k.as_slice() {
            b"Fixed" => pdo.fixed = flag(ctx, v, *at, &what)?,
            b"Mandatory" => pdo.mandatory = flag(ctx, v, *at, &what)?,
            b"Virtual" => pdo.is_virtual = flag(ctx, v, *at, &what)?,
            b"Sm" => pdo.sm = Some(ctx.number(v, *at, &what)?),
            b"Su" => pdo.su = Some(ctx.number(v, *at, &what)?),
            b"OSFac" => pdo.os_factor = Some(ctx.number(v, *at, &what)?),
            b"OSMin" => pdo.os_min = Some(ctx.number(v, *at, &what)?),
            b"OSMax" => pdo.os_max = Some(ctx.number(v, *at, &what)?),
            b"OSIndexInc" => pdo.os_index_inc = Some(ctx.number(v, *at, &what)?),
            _ => {}
        }
    }
    if tag == Tag::RxPdo {
        dev.ecat.rx_pdos.push(pdo);
    } else {
        dev.ecat.tx_pdos.push(pdo);
    }
    Ok(())
}

/// An `Entry` of the PDO `pdo`, with where it is.
fn pdo_entry_start(
    ctx: Ctx,
    dev: &mut RawDevice,
    pdo: Tag,
    attrs: &Attrs,
    offset: usize,
) -> Result<(), ParseError> {
    let tx = pdo == Tag::TxPdo;
    let ordinal = if tx {
        dev.ecat.tx_pdos.len()
    } else {
        dev.ecat.rx_pdos.len()
    };
    let mut entry = PdoEntry::default();
    for (k, v, at) in attrs {
        if k == b"Fixed" {
            entry.fixed = flag(ctx, v, *at, "the Fixed attribute of <Entry>")?;
        }
    }
    if let Some(p) = pdo_of(dev, pdo) {
        p.entries.push(entry);
        let n = p.entries.len() - 1;
        dev.pdo_entry_offsets.push(EntryAt {
            tx,
            pdo: ordinal.saturating_sub(1),
            n,
            offset,
        });
    }
    Ok(())
}

/// `Mailbox` and what is in it (`rest`, the path below it).
fn mailbox_start(
    ctx: Ctx,
    dev: &mut RawDevice,
    rest: &[Tag],
    attrs: &Attrs,
) -> Result<(), ParseError> {
    match rest {
        [] => {
            let mut mb = Mailbox::default();
            for (k, v, at) in attrs {
                if k == b"DataLinkLayer" {
                    mb.data_link_layer =
                        flag(ctx, v, *at, "the DataLinkLayer attribute of <Mailbox>")?;
                }
            }
            dev.ecat.mailbox = Some(mb);
        }
        [Tag::CoE] => {
            let coe = coe_attributes(ctx, attrs)?;
            if let Some(mb) = dev.ecat.mailbox.as_mut() {
                mb.coe = Some(coe);
            }
        }
        [Tag::CoE, Tag::InitCmd, ..] => return init_cmd_start(ctx, dev, &rest[2..], attrs),
        [Tag::FoE] => {
            if let Some(mb) = dev.ecat.mailbox.as_mut() {
                mb.foe = true;
            }
        }
        [Tag::EoE] => {
            if let Some(mb) = dev.ecat.mailbox.as_mut() {
                mb.eoe = true;
            }
        }
        _ => {}
    }
    Ok(())
}

/// The attributes of `CoE`.
fn coe_attributes(ctx: Ctx, attrs: &Attrs) -> Result<CoeFlags, ParseError> {
    let mut coe = CoeFlags {
        segmented_sdo: true,
        ..CoeFlags::default()
    };
    for (k, v, at) in attrs {
        let what = format!("the {} attribute of <CoE>", String::from_utf8_lossy(k));
        let field = match k.as_slice() {
            b"SdoInfo" => &mut coe.sdo_info,
            b"PdoAssign" => &mut coe.pdo_assign,
            b"PdoConfig" => &mut coe.pdo_config,
            b"PdoUpload" => &mut coe.pdo_upload,
            b"CompleteAccess" => &mut coe.complete_access,
            b"SegmentedSdo" => &mut coe.segmented_sdo,
            _ => continue,
        };
        *field = flag(ctx, v, *at, &what)?;
    }
    Ok(coe)
}

/// `CoE/InitCmd` and what is in it (`rest`, the path below it).
fn init_cmd_start(
    ctx: Ctx,
    dev: &mut RawDevice,
    rest: &[Tag],
    attrs: &Attrs,
) -> Result<(), ParseError> {
    match rest {
        [] => {
            let mut cmd = InitCmd::default();
            for (k, v, at) in attrs {
                let what = format!("the {} attribute of <InitCmd>", String::from_utf8_lossy(k));
                let field = match k.as_slice() {
                    b"Fixed" => &mut cmd.fixed,
                    b"CompleteAccess" => &mut cmd.complete_access,
                    b"OverwrittenByModule" => &mut cmd.overwritten_by_module,
                    _ => continue,
                };
                *field = flag(ctx, v, *at, &what)?;
            }
            if let Some(mb) = dev.ecat.mailbox.as_mut() {
                mb.init_cmds.push(cmd);
            }
        }
        [Tag::Index] => {
            let depend = slot_depend(ctx, attrs)?;
            if let Some(cmd) = init_cmd_of(dev) {
                cmd.index_depend = depend;
            }
        }
        [Tag::Data] => {
            let mut adapt = false;
            for (k, v, at) in attrs {
                if k == b"AdaptAutomatically" {
                    adapt = flag(ctx, v, *at, "the AdaptAutomatically attribute of <Data>")?;
                }
            }
            if let Some(cmd) = init_cmd_of(dev) {
                cmd.adapt_automatically = adapt;
            }
        }
        _ => {}
    }
    Ok(())
}

/// `Dc` and the operation modes in it (`rest`, the path below it).
fn dc_start(ctx: Ctx, dev: &mut RawDevice, rest: &[Tag], attrs: &Attrs) -> Result<(), ParseError> {
    match rest {
        [Tag::OpMode] => dev.ecat.op_modes.push(OpMode::default()),
        [Tag::OpMode, which @ (Tag::CycleTimeSync0 | Tag::CycleTimeSync1)] => {
            let mut factor = 1i32;
            for (k, v, at) in attrs {
                if k == b"Factor" {
                    factor = ctx.number(
                        v,
                        *at,
                        &format!("the Factor attribute of <{}>", which.name()),
                    )?;
                }
            }
            if let Some(m) = dev.ecat.op_modes.last_mut() {
                let slot = if *which == Tag::CycleTimeSync0 {
                    &mut m.cycle_time_sync0
                } else {
                    &mut m.cycle_time_sync1
                };
                *slot = Some((0, factor));
            }
        }
        _ => {}
    }
    Ok(())
}

// Where elements end: their text.

/// `Profile/ProfileNo` or `Profile/AddInfo` (`f`) of a module; a number that does not read is left out.
fn profile_number_end(ctx: Ctx, dev: &mut RawDevice, f: Tag, text: &str, at: usize) {
    let what = format!("<Profile>/<{}>", f.name());
    let n = match ctx.number(text, at, &what) {
        Ok(n) => Some(n),
        Err(e) => {
            ctx.warn(at, format!("{}; it is left out", e.message));
            None
        }
    };
    if f == Tag::ProfileNo {
        dev.profile_no = n;
    } else {
        dev.add_info = n;
    }
}

/// What is in `Slots` (`rest`, the path below it).
fn slots_end(
    ctx: Ctx,
    dev: &mut RawDevice,
    rest: &[Tag],
    text: &str,
    at: usize,
    lcid: Option<u32>,
) -> Result<(), ParseError> {
    match rest {
        [Tag::Slot, rest @ ..] => {
            let Some(slot) = dev.ecat.slots.as_mut().and_then(|s| s.slots.last_mut()) else {
                return Ok(());
            };
            match rest {
                // Localized: 1033 wins over the first.
                [Tag::Name] if slot.name.is_empty() || lcid == Some(1033) => {
                    slot.name = text.to_string()
                }
                [Tag::ModuleIdent] => {
                    let ident = ctx.number(text, at, "<Slot>/<ModuleIdent>")?;
                    if let Some(m) = slot.module_idents.last_mut() {
                        m.ident = ident;
                    }
                }
                [Tag::ModuleClass, f] => {
                    if let Some(c) = slot.module_classes.last_mut() {
                        match f {
                            Tag::Class => c.class = text.to_string(),
                            Tag::VendorId => {
                                c.vendor_id =
                                    Some(ctx.number(text, at, "<ModuleClass>/<VendorId>")?)
                            }
                            Tag::Name if c.name.is_empty() || lcid == Some(1033) => {
                                c.name = text.to_string()
                            }
                            _ => {}
                        }
                    }
                }
                _ => {}
            }
        }
        [Tag::ModulePdoGroup] => {
            if let Some(g) = dev
                .ecat
                .slots
                .as_mut()
                .and_then(|s| s.module_pdo_groups.last_mut())
            {
                g.name = text.to_string();
            }
        }
        _ => {}
    }
    Ok(())
}

/// The element `f` of `CoE/InitCmd`.
fn init_cmd_end(
    ctx: Ctx,
    dev: &mut RawDevice,
    f: Tag,
    text: &str,
    at: usize,
) -> Result<(), ParseError> {
    if let Some(cmd) = init_cmd_of(dev) {
        match f {
            Tag::Transition => cmd.transitions.push(text.to_string()),
            Tag::Index => cmd.index = ctx.number(text, at, "<InitCmd>/<Index>")?,
            Tag::SubIndex => cmd.sub = ctx.number(text, at, "<InitCmd>/<SubIndex>")?,
            Tag::Data => cmd.data = ctx.hex(text, at, "<InitCmd>/<Data>")?,
            Tag::Comment => cmd.comment = text.to_string(),
            _ => {}
        }
    }
    Ok(())
}

/// What is in a dictionary's `DataType` (`rest`, the path below it).
fn data_type_end(
    end: TextAt,
    dev: &mut RawDevice,
    rest: &[Tag],
    restrictions: Restrictions,
) -> Result<(), ParseError> {
    let TextAt {
        ctx,
        text,
        at,
        lcid,
    } = end;
    let Some(dt) = dev.data_types.last_mut() else {
        return Ok(());
    };
    match rest {
        [Tag::Name] => dt.name = text.to_string(),
        [Tag::BaseType] => {
            dt.base_type = Some(At {
                text: text.to_string(),
                offset: at,
            })
        }
        [Tag::BitSize] => dt.bit_size = Some(ctx.number(text, at, "<DataType>/<BitSize>")?),
        [Tag::Comment] => dt.comment.offer(lcid, text),
        [Tag::ArrayInfo, Tag::LBound] => {
            if let Some(a) = dt.arrays.last_mut() {
                a.0 = Some(ctx.number(text, at, "<ArrayInfo>/<LBound>")?);
            }
        }
        [Tag::ArrayInfo, Tag::Elements] => {
            if let Some(a) = dt.arrays.last_mut() {
                a.1 = Some(ctx.number(text, at, "<ArrayInfo>/<Elements>")?);
            }
        }
        [Tag::SubItem, rest @ ..] => {
            if let Some(si) = dt.subitems.last_mut() {
                sub_item_end(end, si, rest, restrictions)?;
            }
        }
        _ => {}
    }
    Ok(())
}

/// What is in a `SubItem` of a `DataType` (`rest`, the path below it).
fn sub_item_end(
    end: TextAt,
    si: &mut RawSubItem,
    rest: &[Tag],
    restrictions: Restrictions,
) -> Result<(), ParseError> {
    let TextAt {
        ctx,
        text,
        at,
        lcid,
    } = end;
    match rest {
        [Tag::SubIdx] => si.sub_idx = Some(ctx.number(text, at, "<SubItem>/<SubIdx>")?),
        [Tag::Name] => si.name = text.to_string(),
        [Tag::Type] => {
            si.type_name = At {
                text: text.to_string(),
                offset: at,
            }
        }
        [Tag::BitSize] => si.bit_size = Some(ctx.number(text, at, "<SubItem>/<BitSize>")?),
        [Tag::BitOffs] => {
            let _: u32 = ctx.number(text, at, "<SubItem>/<BitOffs>")?;
        }
        [Tag::Comment] => si.comment.offer(lcid, text),
        [Tag::Flags, f] => {
            let flags = si.flags.get_or_insert_with(RawFlags::default);
            read_flag(ctx, flags, *f, text, at, restrictions)?;
        }
        _ => {}
    }
    Ok(())
}

/// What is in a dictionary's `Object` (`rest`, the path below it).
fn object_end(
    end: TextAt,
    dev: &mut RawDevice,
    rest: &[Tag],
    restrictions: Restrictions,
) -> Result<(), ParseError> {
    let TextAt {
        ctx,
        text,
        at,
        lcid,
    } = end;
    let Some(o) = dev.objects.last_mut() else {
        return Ok(());
    };
    match rest {
        [Tag::Index] => o.index = Some(ctx.number(text, at, "<Object>/<Index>")?),
        [Tag::Name] => o.name.offer(lcid, text),
        [Tag::Comment] => o.comment.offer(lcid, text),
        [Tag::Type] => {
            o.type_name = At {
                text: text.to_string(),
                offset: at,
            }
        }
        [Tag::BitSize] => o.bit_size = Some(ctx.number(text, at, "<Object>/<BitSize>")?),
        [Tag::Info, Tag::SubItem, Tag::Name] => {
            if let Some(si) = o.sub_infos.last_mut() {
                si.0 = text.to_string();
            }
        }
        [Tag::Info, Tag::SubItem, Tag::Info, f] => {
            if let Some(si) = o.sub_infos.last_mut() {
                read_info(ctx, &mut si.1, *f, text, at)?;
            }
        }
        [Tag::Info, f] => read_info(ctx, &mut o.info, *f, text, at)?,
        [Tag::Flags, f] => {
            let flags = o.flags.get_or_insert_with(RawFlags::default);
            read_flag(ctx, flags, *f, text, at, restrictions)?;
        }
        _ => {}
    }
    Ok(())
}

/// An `RxPdo` or `TxPdo` and what is in it (`rel`, the path from the PDO element).
fn pdo_end(
    ctx: Ctx,
    dev: &mut RawDevice,
    rel: &[Tag],
    text: &str,
    at: usize,
    lcid: Option<u32>,
) -> Result<(), ParseError> {
    let (kind, rest) = match rel {
        [_] if dev.in_ref_pdo => {
            dev.in_ref_pdo = false;
            return Ok(());
        }
        [_, ..] if dev.in_ref_pdo => return Ok(()),
        [kind, rest @ ..] => (*kind, rest),
        [] => return Ok(()),
    };
    let Some(p) = pdo_of(dev, kind) else {
        return Ok(());
    };
    match rest {
        [Tag::Index] => p.index = ctx.number(text, at, &format!("<{}>/<Index>", kind.name()))?,
        // Localized: 1033 wins over the first.
        [Tag::Name] if p.name.is_empty() || lcid == Some(1033) => p.name = text.to_string(),
        [Tag::Exclude] => {
            let index = ctx.number(text, at, "<Exclude>")?;
            if let Some(x) = p.exclude.last_mut() {
                x.index = index;
            }
        }
        [Tag::Entry, f] => {
            if let Some(en) = p.entries.last_mut() {
                match f {
                    Tag::Index => en.index = ctx.number(text, at, "<Entry>/<Index>")?,
                    Tag::SubIndex => en.sub = ctx.number(text, at, "<Entry>/<SubIndex>")?,
                    Tag::BitLen => en.bit_len = ctx.number(text, at, "<Entry>/<BitLen>")?,
                    Tag::Name if en.name.is_empty() || lcid == Some(1033) => {
                        en.name = text.to_string()
                    }
                    Tag::DataType => en.data_type = text.to_string(),
                    Tag::Comment => en.comment = text.to_string(),
                    _ => {}
                }
            }
        }
        _ => {}
    }
    Ok(())
}

/// The element `f` of a `Dc/OpMode`; `tag` names it in messages.
fn op_mode_end(
    ctx: Ctx,
    dev: &mut RawDevice,
    tag: Tag,
    f: Tag,
    text: &str,
    at: usize,
) -> Result<(), ParseError> {
    let what = || format!("<{}>", tag.name());
    let Some(m) = dev.ecat.op_modes.last_mut() else {
        return Ok(());
    };
    match f {
        Tag::Name => m.name = text.to_string(),
        Tag::Desc => m.desc = text.to_string(),
        Tag::AssignActivate => m.assign_activate = ctx.number(text, at, "<AssignActivate>")?,
        Tag::CycleTimeSync0 | Tag::CycleTimeSync1 => {
            let v: u32 = ctx.number(text, at, &what())?;
            let slot = if f == Tag::CycleTimeSync0 {
                &mut m.cycle_time_sync0
            } else {
                &mut m.cycle_time_sync1
            };
            let factor = slot.map_or(1, |s| s.1);
            *slot = Some((v, factor));
        }
        Tag::ShiftTimeSync0 => m.shift_time_sync0 = Some(ctx.number(text, at, &what())?),
        Tag::ShiftTimeSync1 => m.shift_time_sync1 = Some(ctx.number(text, at, &what())?),
        _ => {}
    }
    Ok(())
}

/// The element `f` of `Eeprom`.
fn eeprom_end(
    ctx: Ctx,
    dev: &mut RawDevice,
    f: Tag,
    text: &str,
    at: usize,
) -> Result<(), ParseError> {
    if let Some(ee) = dev.ecat.eeprom.as_mut() {
        match f {
            Tag::ByteSize => ee.byte_size = ctx.number(text, at, "<Eeprom>/<ByteSize>")?,
            Tag::ConfigData => ee.config_data = ctx.hex(text, at, "<ConfigData>")?,
            Tag::BootStrap => ee.boot_strap = ctx.hex(text, at, "<BootStrap>")?,
            _ => {}
        }
    }
    Ok(())
}
