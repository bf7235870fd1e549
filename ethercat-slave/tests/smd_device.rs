//! The SMD model ([`SmdModel`]) as a device of the one lifecycle (`od::hook::Device`): a timeout
//! is one process-data exchange, due one exchange period after the last; and every write into an
//! [`SmdUnit`] goes through the hook path, so that what the model refuses changes nothing.

use std::time::{Duration, Instant};

use ds402::od::hook::{Device as _, DeviceHook as _};
use ds402::od::object::SubObject;
use ds402::od::{AbortCode, AccessType, Address, DataType, Value};
use ds402::smd::config::EncoderKind;
use ds402::smd::indexer::{cmd0, cmd1, stat0, stat1, Outputs};
use ethercat_slave::smd::binding::{dictionary, Device, SmdModel, SmdUnit};

const MS: Duration = Duration::from_millis(1);

fn unit() -> SmdUnit {
    SmdUnit::new(Device::Smd23kB, EncoderKind::Incremental).expect("the fixture binds")
}

fn model(u: &mut SmdUnit) -> &mut SmdModel {
    u.model_mut()
}

/// A timeout is one exchange, due one period after the last: none before the indexer starts;
/// started at t0 with 1 ms, due at t0 + 1 ms. Each timeout answers exactly what one exchange of the
/// indexer answers at that instant: the power-up inputs (0x4408: Module_OK, Position_Invalid,
/// Stopped); the output image delivered before it (Enable_Driver, Preset Position) taken as new
/// output data (0x4008, STATUS_word1 0xA000: Drive_Is_Enabled, Command_Acknowledge); a timeout
/// with no image since, an exchange without new output data (SMD-R6-073: no edge, the command
/// still in force). A reset is a power cycle (0x4408 again), the exchanges going on.
#[test]
fn a_timeout_is_one_exchange() {
    let t0 = Instant::now();
    let mut u = unit();
    assert_eq!(model(&mut u).poll_timeout(), None);
    u.indexer_mut().start(t0, MS);
    assert_eq!(model(&mut u).poll_timeout(), Some(t0 + MS));

    let mut ix = u.indexer().clone();
    model(&mut u).handle_timeout(t0 + MS);
    assert_eq!(u.inputs(), ix.exchange_held(t0 + MS));
    assert_eq!(u.inputs().status0, 0x4408);
    assert_eq!(model(&mut u).poll_timeout(), Some(t0 + 2 * MS));

    let out = Outputs {
        cmd0: cmd0::PRESET_POSITION,
        cmd1: cmd1::ENABLE_DRIVER,
        ..Outputs::default()
    };
    u.write_outputs(t0 + 2 * MS, &out);
    assert_eq!(u.outputs(), out);
    model(&mut u).handle_timeout(t0 + 2 * MS);
    let i = ix.exchange(t0 + 2 * MS, out);
    assert_eq!(u.inputs(), i);
    assert_eq!((i.status0, i.status1), (0x4008, 0xA000));
    assert_eq!(model(&mut u).poll_timeout(), Some(t0 + 3 * MS));

    model(&mut u).handle_timeout(t0 + 3 * MS);
    let i = ix.exchange_held(t0 + 3 * MS);
    assert_eq!(u.inputs(), i);
    assert_eq!(
        i.status1 & stat1::COMMAND_ACKNOWLEDGE,
        stat1::COMMAND_ACKNOWLEDGE
    );

    model(&mut u).reset(t0 + 3 * MS);
    model(&mut u).handle_timeout(t0 + 4 * MS);
    assert_eq!(u.inputs().status0, 0x4408);
    assert_eq!(model(&mut u).poll_timeout(), Some(t0 + 5 * MS));
}

/// SMD-R1-022: a synchronisation is the SYNC0 event at its instant. With DC_Sync (CFG_Word_1 =
/// 0x0043) a Relative move taken at the timeout of t waits; synchronised at t + 500 µs it starts at
/// t + 1,020 µs: Stopped at the timeout of t + 1 ms, moving at t + 2 ms.
#[test]
fn smd_r1_022_sync_is_the_sync0_event_at_its_instant() {
    let t0 = Instant::now();
    let mut u = unit();
    u.indexer_mut().start(t0, MS);
    u.sdo_write(t0, 0x8010, 2, &0x0043u16.to_le_bytes())
        .unwrap();
    let mut out = Outputs {
        cmd0: cmd0::PRESET_POSITION,
        cmd1: cmd1::ENABLE_DRIVER,
        velocity: 10_000,
        acceleration: 10,
        deceleration: 10,
        ..Outputs::default()
    };
    let mut t = t0;
    for cmd in [cmd0::PRESET_POSITION, 0, cmd0::RELATIVE_MOVE] {
        t += MS;
        out.cmd0 = cmd;
        out.position = if cmd == cmd0::RELATIVE_MOVE { 1_000 } else { 0 };
        u.write_outputs(t, &out);
        model(&mut u).handle_timeout(t);
    }
    assert_ne!(u.inputs().status0 & stat0::STOPPED, 0, "waits for SYNC0");
    model(&mut u).sync(t + Duration::from_micros(500));
    model(&mut u).handle_timeout(t + MS);
    assert_ne!(u.inputs().status0 & stat0::STOPPED, 0, "1,020 µs after t");
    model(&mut u).handle_timeout(t + 2 * MS);
    assert_eq!(u.inputs().status0 & stat0::STOPPED, 0, "moving");
}

/// A download the model refuses changes nothing. On a dictionary with an entry the model does not
/// bind (0x8010:08, writable: the dictionary takes the value), the download is refused with the
/// model's abort code (0x06010000): neither the dictionary nor the indexer changes, and in
/// particular the position stays valid (a configuration write would make it invalid,
/// SMD-R2-012). The inputs are the indexer's: the model refuses them whatever the access.
#[test]
fn smd_r2_012_a_download_the_model_refuses_changes_nothing() {
    let t0 = Instant::now();
    let mut dict = dictionary(Device::Smd23kB).unwrap();
    dict.object_mut(0x8010).unwrap().subs.insert(
        8,
        SubObject::new("Spare", DataType::Unsigned16, AccessType::Rw).with_default(Value::Uint(0)),
    );
    let mut u = SmdUnit::with_dictionary(Device::Smd23kB, dict, EncoderKind::Incremental).unwrap();
    u.write_outputs(
        t0,
        &Outputs {
            cmd0: cmd0::PRESET_POSITION,
            ..Outputs::default()
        },
    );
    u.cycle(MS);
    u.write_outputs(t0, &Outputs::default());
    assert_eq!(u.cycle(MS).status0 & stat0::POSITION_INVALID, 0);

    let dict = u.dict().clone();
    let indexer = format!("{:?}", u.indexer());
    assert_eq!(
        u.sdo_write(t0, 0x8010, 8, &[1, 0]),
        Err(AbortCode::UnsupportedAccess)
    );
    assert_eq!(u32::from(AbortCode::UnsupportedAccess), 0x0601_0000);
    assert_eq!(u.dict(), &dict);
    assert_eq!(format!("{:?}", u.indexer()), indexer);
    assert_eq!(u.cycle(MS).status0 & stat0::POSITION_INVALID, 0);

    assert_eq!(
        u.model().check(Address::new(0x6000, 1), &[0, 0]),
        Err(AbortCode::ReadOnly)
    );
    // A confirmed download to the model's own configuration is taken (and invalidates the
    // position, SMD-R2-012).
    u.sdo_write(t0, 0x8010, 6, &50u16.to_le_bytes()).unwrap();
    assert_ne!(u.cycle(MS).status0 & stat0::POSITION_INVALID, 0);
}
