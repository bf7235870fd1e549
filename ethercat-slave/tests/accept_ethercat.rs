//! `scripts/accept-402-ethercat`, the acceptance runner of EtherCAT drives, on the corpus beside the
//! checkout and on the MDP 742 test ESIs: every device with drive axes (or that looks like a drive)
//! run alone by `ethercat-node` on a veth pair of its own and driven by SOEM (pysoem): Op with DC,
//! 0x6502, each axis enabled, a csp ramp of 1,000 set-points to its exact target and one second
//! standing there. The table it prints is asserted row by row: the drives that pass, and the
//! reason each of the others fails (a layout of the drive profile ethercat-node does not run, PDOs
//! no master may assign); a device whose ESI lists no 0x6502 passes without that check.
//!
//! Needs root (network namespaces, veth pairs, raw sockets), pysoem and the corpus: without any of
//! them the test fails and says why; it is never skipped.

use std::process::Command;
use std::time::Duration;

#[path = "common/pysoem.rs"]
#[allow(dead_code)]
mod pysoem_master;

/// The runner on `dir` with `extra`: its exit status and its table.
fn runner(dir: &str, extra: &[&str]) -> (i32, String) {
    pysoem_master::preflight();
    let bin = testkit::cargo_binary("ethercat-slave", "ethercat-node", &[]);
    let script = testkit::root().join("scripts/accept-402-ethercat");
    let testkit::Finished {
        status,
        stdout,
        stderr,
    } = testkit::run_for_at_most(
        Command::new("python3")
            .arg(script)
            .arg(dir)
            .arg("--bin")
            .arg(&bin)
            .args(extra),
        Duration::from_secs(600),
    );
    let status = status.unwrap_or_else(|| panic!("the runner ran over 600 s\n{stdout}\n{stderr}"));
    let code = status
        .code()
        .unwrap_or_else(|| panic!("the runner was killed\n{stdout}\n{stderr}"));
    assert_ne!(code, 2, "the runner could not run:\n{stderr}");
    println!("{stdout}");
    (code, stdout)
}

fn rows(table: &str) -> Vec<&str> {
    table.lines().filter(|l| l.starts_with("| ")).collect()
}

const NO_AXIS: &str = "but no CiA 402 axis (0x6040 and 0x6041 UNSIGNED16 at sub-index 0, at \
                       0x6000 + 0x800·axis) and no MDP 742 channel (0x7010:01 and 0x6010:01 \
                       UNSIGNED16 and a target, at + 0x100·channel)";

/// The corpus: 17 devices look like drives, 6 pass (Copley's two axes, both Elmo files' two
/// devices, Ingenia); each of the others fails with the first thing that stands in the way.
#[test]
fn the_corpus_drives_pass_or_say_why_not() {
    let corpus = testkit::root().join("../shared/corpus/esi");
    assert!(
        corpus.is_dir(),
        "{} is missing: the runner reads the corpus beside the checkout",
        corpus.display()
    );
    let (code, table) = runner(corpus.to_str().unwrap(), &[]);
    let siitool = |device: &str| {
        format!(
            "| siitool-Somanet_CiA402-multi.xml | {device} | FAIL | PDO entries of a drive \
             (\"Controlword\" at 0x1600:01, a mode of operation), {NO_AXIS} |"
        )
    };
    let no_assign = |file: &str, device: &str| {
        format!(
            "| {file} | {device} | FAIL | the RxPDOs do not map 0x6040:00, 0x607A:00 and the ESI \
             lets no master change their assignment |"
        )
    };
    let expected: Vec<String> = vec![
        "| file | device | result | reason |".into(),
        "| copley-XE2_4.60.xml | XE2 | pass | 2 axis/axes at their targets, 56 bytes of process \
         data |"
            .into(),
        "| dls-Beckhoff_AX2xxx.xml | AX2000-B110 | FAIL | no RxPDO the ESI lets a master assign \
         maps 0x607A:00 |"
            .into(),
        "| elmo-ECAT_00010420_V11.xml | Elmo Drive (0x00030924) | pass | 1 axis/axes at their \
         targets, 20 bytes of process data |"
            .into(),
        "| elmo-ECAT_00010420_V11.xml | Elmo Drive (0x00030925) | pass | 1 axis/axes at their \
         targets, 20 bytes of process data |"
            .into(),
        format!(
            "| etg2001-ModulesSlots_CiA402.xml | Drive1 | FAIL | the controlword of CiA 402 axis \
             0 at 0x6040:00 (\"ControlWord\"), {NO_AXIS} |"
        ),
        no_assign("hwdm-BogusServo.xml", "B090.SO.3.0"),
        no_assign("hwdm-BogusServo.xml", "B090.SO.3.1"),
        "| hwdm-Elmo_rev_10420_only.xml | Elmo Drive (0x00030924) | pass | 1 axis/axes at their \
         targets, 20 bytes of process data |"
            .into(),
        "| hwdm-Elmo_rev_10420_only.xml | Elmo Drive (0x00030925) | pass | 1 axis/axes at their \
         targets, 20 bytes of process data |"
            .into(),
        "| ingenia-eve-xcr-e.xml | EVE-XCR-E | pass | 1 axis/axes at their targets, 22 bytes of \
         process data |"
            .into(),
        no_assign("pollen-Orbita3d.xml", "Orbita3d"),
        siitool("CiA402 Motor Control Device"),
        siitool("CiA402 Motor Control Gedings (0x00000302)"),
        siitool("CiA402 Motor Control Gedings (0x00000303)"),
        siitool("CiA402 Motor Control Gedings (0x00000304)"),
        siitool("CiA402 Motor Control Gedings (0x00000305)"),
        "| somanet-CiA402-single.xml | CiA402 Motor Control Device | pass | 1 axis/axes at their \
         targets, 26 bytes of process data |"
            .into(),
    ];
    assert_eq!(rows(&table), expected);
    assert!(
        table.contains("\n7 of 17 drive devices pass on EtherCAT.\n"),
        "{table}"
    );
    assert_eq!(code, 1, "a device fails: exit status 1");
}

/// The MDP 742 test ESIs: the one-channel servo terminal (PDOs 0x1600 and 0x1606 assigned for csp)
/// and both channels of the stepper terminal pass, with servo motors and with stepper motors.
#[test]
fn the_mdp742_terminals_pass_with_servos_and_with_steppers() {
    let dir = testkit::root().join("ethercat-slave/tests/esi");
    for motor in ["servo", "stepper"] {
        let (code, table) = runner(dir.to_str().unwrap(), &["--motor", motor]);
        assert_eq!(
            rows(&table),
            [
                "| file | device | result | reason |",
                "| mdp742-servo-1ch.xml | EL7211-0010 | pass | 1 axis/axes at their targets, 16 \
                 bytes of process data |",
                "| mdp742-stepper-2ch.xml | EL7062 | pass | 2 axis/axes at their targets, 32 bytes \
                 of process data |",
            ],
            "{motor}"
        );
        assert!(
            table.contains("\n2 of 2 drive devices pass on EtherCAT.\n"),
            "{table}"
        );
        assert_eq!(code, 0, "{motor}");
    }
}
