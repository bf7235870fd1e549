//! Element text and attribute values of an ESI that several elements share: booleans, slot
//! dependencies, access flags and the values of `Info`.

use super::{clip, At, Ctx, RawDevice, RawFlags, RawInfo, Tag};
use crate::device::{InitCmd, Pdo, SlotDepend};
use crate::error::ParseError;
use crate::object::{Access, AccessType, EcatStates, PdoMapping};
use crate::xml;

pub(super) fn init_cmd_of(dev: &mut RawDevice) -> Option<&mut InitCmd> {
    dev.ecat
        .mailbox
        .as_mut()
        .and_then(|m| m.init_cmds.last_mut())
}

pub(super) fn pdo_of(dev: &mut RawDevice, tag: Tag) -> Option<&mut Pdo> {
    if tag == Tag::RxPdo {
        dev.ecat.rx_pdos.last_mut()
    } else {
        dev.ecat.tx_pdos.last_mut()
    }
}

/// The `DependOnSlot` and `DependOnSlotGroup` attributes of an element.
pub(super) fn slot_depend(
    ctx: Ctx,
    attrs: &[(Vec<u8>, String, usize)],
) -> Result<SlotDepend, ParseError> {
    let mut d = SlotDepend::default();
    for (k, v, at) in attrs {
        let which = match k.as_slice() {
            b"DependOnSlot" => &mut d.slot,
            b"DependOnSlotGroup" => &mut d.slot_group,
            _ => continue,
        };
        *which = flag(
            ctx,
            v,
            *at,
            &format!("the {} attribute", String::from_utf8_lossy(k)),
        )?;
    }
    Ok(d)
}

/// The `Enable` attribute of `Sm`: a number 0..255 (the SII enable byte), or `true`/`false`.
pub(super) fn enable(ctx: Ctx, text: &str, at: usize, what: &str) -> Result<u8, ParseError> {
    match ctx.number::<u8>(text, at, what) {
        Ok(n) => Ok(n),
        Err(e) => xml::parse_bool(text).map(u8::from).ok_or(e),
    }
}

/// A boolean attribute (`1`, `0`, `true`, `false`).
pub(super) fn flag(ctx: Ctx, text: &str, at: usize, what: &str) -> Result<bool, ParseError> {
    xml::parse_bool(text).ok_or_else(|| {
        ctx.err(
            at,
            format!(
                "expected 1, 0, true or false in {what}, found `{}`",
                clip(text)
            ),
        )
    })
}

pub(super) fn read_flag(
    ctx: Ctx,
    flags: &mut RawFlags,
    tag: Tag,
    text: &str,
    at: usize,
    restrictions: (Option<EcatStates>, Option<EcatStates>),
) -> Result<(), ParseError> {
    match tag {
        Tag::Access => {
            let kind = AccessType::parse(text).ok_or_else(|| {
                ctx.err(
                    at,
                    format!("expected ro, rw or wo in <Access>, found `{}`", clip(text)),
                )
            })?;
            flags.access = Some(Access {
                kind,
                read_states: restrictions.0,
                write_states: restrictions.1,
            });
        }
        Tag::PdoMapping => {
            let pdo = match text.to_ascii_uppercase().as_str() {
                "R" => PdoMapping::Rpdo,
                "T" => PdoMapping::Tpdo,
                "RT" | "TR" => PdoMapping::Both,
                "" => PdoMapping::None,
                _ => {
                    return Err(ctx.err(
                        at,
                        format!(
                            "expected R, T, RT or TR in <PdoMapping>, found `{}`",
                            clip(text)
                        ),
                    ))
                }
            };
            flags.pdo = Some(pdo);
        }
        _ => {}
    }
    Ok(())
}

pub(super) fn read_info(
    ctx: Ctx,
    info: &mut RawInfo,
    tag: Tag,
    text: &str,
    at: usize,
) -> Result<(), ParseError> {
    let keep = || At {
        text: text.to_string(),
        offset: at,
    };
    match tag {
        Tag::DefaultData => info.default_data = Some((ctx.hex(text, at, "<DefaultData>")?, at)),
        Tag::MinData | Tag::MaxData => {
            let what = if tag == Tag::MinData {
                "<MinData>"
            } else {
                "<MaxData>"
            };
            let bytes = match ctx.hex(text, at, what) {
                Ok(b) => Some((b, at)),
                Err(e) => {
                    ctx.warn(at, format!("{}; the limit is dropped", e.message));
                    None
                }
            };
            if tag == Tag::MinData {
                info.min_data = bytes;
            } else {
                info.max_data = bytes;
            }
        }
        Tag::DefaultValue => info.default_value = Some(keep()),
        Tag::MinValue => info.min_value = Some(keep()),
        Tag::MaxValue => info.max_value = Some(keep()),
        Tag::DefaultString => info.default_string = Some(keep()),
        Tag::Unit => match crate::xml::parse_number(text).and_then(|v| u32::try_from(v).ok()) {
            Some(code) => info.unit = Some(code),
            None => ctx.warn(
                at,
                format!("<Unit> {text:?} is no 32-bit unit code; the unit is dropped"),
            ),
        },
        _ => {}
    }
    Ok(())
}
