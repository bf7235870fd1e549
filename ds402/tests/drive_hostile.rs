//! Whatever a master writes, in whatever order and at whatever times, the drive neither panics nor
//! takes time out of proportion: random SDO downloads of random bytes to every object of the axis,
//! random control words, random waits and SYNCs. After each step the status word is one of the
//! states of CiA 402-2 and every object reads back.

mod drive_rig;

use drive_rig::{dictionary, Rig};
use ds402::cia402::State;
use ds402::drive::{DriveConfig, MotorKind};
use proptest::prelude::*;

/// The objects of the rig's dictionary, as (index, sub).
fn entries() -> Vec<(u16, u8)> {
    let dict = dictionary(&[]);
    dict.objects()
        .flat_map(|o| o.subs.keys().map(move |s| (o.index, *s)))
        .collect()
}

#[derive(Debug, Clone)]
enum Step {
    Write(usize, Vec<u8>),
    Control(u16),
    Wait(u64),
    Sync(u64),
}

fn step() -> impl Strategy<Value = Step> {
    prop_oneof![
        (any::<usize>(), proptest::collection::vec(any::<u8>(), 0..9))
            .prop_map(|(k, b)| Step::Write(k, b)),
        prop_oneof![
            Just(0x06u16),
            Just(0x07),
            Just(0x0F),
            Just(0x1F),
            Just(0x3F),
            Just(0x5F),
            Just(0x80),
            Just(0x0B),
            Just(0x010F),
            any::<u16>()
        ]
        .prop_map(Step::Control),
        (0u64..50).prop_map(Step::Wait),
        (1u64..5).prop_map(Step::Sync),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_writes_and_times_never_panic(
        steps in proptest::collection::vec(step(), 1..120),
        stepper in any::<bool>(),
    ) {
        let mut config = DriveConfig::default();
        if stepper {
            config.motor.kind = MotorKind::Stepper;
        }
        let mut r = Rig::new(dictionary(&[]), config);
        let all = entries();
        for s in steps {
            match s {
                Step::Write(k, bytes) => {
                    let (index, sub) = all[k % all.len()];
                    let _ = r.write_bytes(index, sub, &bytes);
                }
                Step::Control(cw) => {
                    let _ = r.write(0x6040, 0, i64::from(cw));
                }
                Step::Wait(ms) => r.wait(ms),
                Step::Sync(ms) => {
                    let to = r.ms() + ms;
                    r.sync_at(to);
                }
            }
            let sw = r.sw();
            prop_assert!(State::from_status_word(sw).is_some(), "status word {sw:#06x}");
            for &(index, sub) in &all {
                let _ = r.read(index, sub);
            }
        }
    }
}
