//! `smd simulate`: the script parser's messages, runs against the indexer model, the table, the chart,
//! and the example scripts of `ds402/examples/smd` through the binary.

mod smd_bin;

use std::path::{Path, PathBuf};
use std::time::Duration;

use ds402::smd::config::{Configuration, EncoderKind};
use ds402::smd::indexer::stat0;
use ds402::smd::simulate::{
    format_line, header, parse_time, run, Action, Field, Options, Script, Trace,
};
use smd_bin::smd;

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/smd")
}

/// The message of the script's error.
fn error(source: &str) -> String {
    Script::parse(source, "script.smd").unwrap_err().to_string()
}

fn lines(trace: &Trace) -> Vec<String> {
    trace.lines.iter().map(|s| format_line(trace, s)).collect()
}

const RELATIVE: &str = "\
# A Relative move of 5000 steps.
at 0ms   out cmd1=0x8000 velocity=10000 acceleration=100 deceleration=100
at 10ms  out cmd0=0x0200                 # Preset Position to 0
at 20ms  out cmd0=0
at 30ms  out cmd0=0x0002 position=5000   # Relative Move
at 40ms  out cmd0=0
until 1s
";

#[test]
fn times_take_us_ms_and_s() {
    assert_eq!(parse_time("250us"), Some(Duration::from_micros(250)));
    assert_eq!(parse_time("250µs"), Some(Duration::from_micros(250)));
    assert_eq!(parse_time("20ms"), Some(Duration::from_millis(20)));
    assert_eq!(parse_time("1.5s"), Some(Duration::from_millis(1500)));
    assert_eq!(parse_time("0.25ms"), Some(Duration::from_micros(250)));
    assert_eq!(parse_time("0s"), Some(Duration::ZERO));
    for bad in [
        "",
        "1",
        "s",
        "1.s",
        ".5s",
        "-1ms",
        "1 ms",
        "1e3ms",
        "1.0000000001s",
        "2min",
    ] {
        assert_eq!(parse_time(bad), None, "{bad:?}");
    }
}

#[test]
fn a_script_parses_into_its_statements() {
    let script = Script::parse(
        "unit absolute\n\
         cycle 500us\n\
         config cfg_word_0 0x0405   # E-Stop, encoder\n\
         config 8010:03 200\n\
         \n\
         at 0ms out cmd1=0x8000 position=-0x10 velocity=0b1010\n\
         at 1ms input 2 on\n\
         at 1ms config MOTOR_CURRENT 20\n\
         until 2.5ms\n",
        "s.smd",
    )
    .unwrap();
    assert_eq!(script.kind, EncoderKind::Absolute);
    assert_eq!(script.cycle, Duration::from_micros(500));
    assert_eq!(
        script.config,
        Configuration {
            cfg0: 0x0405,
            starting_speed: 200,
            ..Configuration::default()
        }
    );
    assert_eq!(script.until, Duration::from_micros(2500));
    let actions: Vec<(u128, usize, &Action)> = script
        .events
        .iter()
        .map(|e| (e.time.as_micros(), e.line, &e.action))
        .collect();
    assert_eq!(
        actions,
        [
            (
                0,
                6,
                &Action::Out(vec![
                    (Field::Cmd1, 0x8000),
                    (Field::Position, -16),
                    (Field::Velocity, 10)
                ])
            ),
            (
                1000,
                7,
                &Action::Input {
                    n: 2,
                    current: true
                }
            ),
            (1000, 8, &Action::Config { sub: 7, value: 20 }),
        ]
    );
}

#[test]
fn parse_errors_name_the_line_and_what_is_wrong() {
    let cases: &[(&str, &str)] = &[
        (
            "at 0ms out cmd1=0x8000\n\n# comment\nat 1ms out cmd0=2\n\n\nat 2ms out veloc=100\nuntil 1s\n",
            "script.smd:7: unknown output field \"veloc\" (expected cmd0, cmd1, position, velocity, \
             acceleration, deceleration, motor_current or jerk)",
        ),
        (
            "at 20ms out cmd0=1\nat 10ms out cmd0=0\nuntil 1s\n",
            "script.smd:2: time 10ms is before the previous statement's time 20ms (times must not go \
             backwards)",
        ),
        (
            "at 0ms out velocity=-5\nuntil 1s\n",
            "script.smd:1: velocity = -5 is out of range (0 to 4294967295, UNSIGNED32)",
        ),
        (
            "at 0ms out cmd0=0x10000\nuntil 1s\n",
            "script.smd:1: cmd0 = 0x10000 is out of range (0 to 65535, UNSIGNED16)",
        ),
        (
            "at 0ms out position=2147483648\nuntil 1s\n",
            "script.smd:1: position = 2147483648 is out of range (-2147483648 to 2147483647, INTEGER32)",
        ),
        (
            "at 0ms out jerk=12a\nuntil 1s\n",
            "script.smd:1: \"12a\" is not a number (decimal, 0x hex or 0b binary)",
        ),
        (
            "at 0ms out cmd0 = 2\nuntil 1s\n",
            "script.smd:1: expected FIELD=VALUE, found \"cmd0\"",
        ),
        (
            "at 0ms out\nuntil 1s\n",
            "script.smd:1: out needs at least one FIELD=VALUE: at TIME out FIELD=VALUE ...",
        ),
        (
            "at 5 out cmd0=1\nuntil 1s\n",
            "script.smd:1: \"5\" is not a time (a number with us, ms or s, e.g. 250us, 20ms or 1.5s)",
        ),
        (
            "at 1.5ms out cmd0=1\nuntil 1s\n",
            "script.smd:1: time 1.5ms is not a whole number of cycles (the cycle is 1ms)",
        ),
        (
            "cycle 100us\nuntil 1s\n",
            "script.smd:1: cycle 100us is out of range (250us to 100ms)",
        ),
        (
            "at 0ms out cmd0=1\ncycle 2ms\nuntil 1s\n",
            "script.smd:2: cycle must come before the first at",
        ),
        (
            "cycle 2ms\ncycle 4ms\nuntil 1s\n",
            "script.smd:2: a second cycle statement (the first is on line 1)",
        ),
        (
            "cycle 2ms\nunit absolute\nuntil 1s\n",
            "script.smd:2: unit must be the first statement",
        ),
        (
            "unit relative\nuntil 1s\n",
            "script.smd:1: unknown encoder kind \"relative\" (expected incremental or absolute)",
        ),
        (
            "config cfg_word_3 1\nuntil 1s\n",
            "script.smd:1: unknown configuration entry \"cfg_word_3\" (expected cfg_word_0, \
             cfg_word_1, starting_speed, motor_resolution, encoder_resolution, \
             idle_current_reduction, motor_current or 8010:01 to 8010:07)",
        ),
        (
            "config 8010:08 1\nuntil 1s\n",
            "script.smd:1: unknown configuration entry \"8010:08\" (expected cfg_word_0, \
             cfg_word_1, starting_speed, motor_resolution, encoder_resolution, \
             idle_current_reduction, motor_current or 8010:01 to 8010:07)",
        ),
        (
            "config motor_resolution 70000\nuntil 1s\n",
            "script.smd:1: motor_resolution = 70000 is out of range (0 to 65535, UNSIGNED16)",
        ),
        (
            "config starting_speed\nuntil 1s\n",
            "script.smd:1: config needs a name and a value: config NAME VALUE",
        ),
        (
            "at 0ms out cmd0=1\nconfig cfg_word_0 5\nuntil 1s\n",
            "script.smd:2: config after the first at needs a time: at TIME config NAME VALUE",
        ),
        (
            "at 0ms input 3 on\nuntil 1s\n",
            "script.smd:1: unknown input \"3\" (expected 1 or 2)",
        ),
        (
            "at 0ms input 1 high\nuntil 1s\n",
            "script.smd:1: expected on or off, found \"high\"",
        ),
        (
            "at 0ms output cmd0=1\nuntil 1s\n",
            "script.smd:1: unknown action \"output\" after the time (expected out, input or config)",
        ),
        (
            "at 0ms\nuntil 1s\n",
            "script.smd:1: at needs a time and an action: at TIME out|input|config ...",
        ),
        (
            "wait 10ms\n",
            "script.smd:1: unknown statement \"wait\" (expected unit, cycle, config, at or until)",
        ),
        (
            "at 1s out cmd0=1\nuntil 1s\n",
            "script.smd:2: until 1s is not after the last statement's time 1s",
        ),
        ("until 0ms\n", "script.smd:1: until 0ms leaves no cycle to run"),
        (
            "until 3601s\n",
            "script.smd:1: until 3601s is beyond the longest run of 1 hour",
        ),
        (
            "at 0ms out cmd0=1\nuntil 1s\nat 2s out cmd0=0\n",
            "script.smd:3: nothing may follow until (line 2)",
        ),
        (
            "at 0ms out cmd0=1\n",
            "script.smd: no until statement (the end of the run is required, as the last statement)",
        ),
    ];
    for (source, message) in cases {
        assert_eq!(&error(source), message, "{source}");
    }
}

/// A Relative move of 5000 steps: the exact lines at the status changes of the start (Enable_Driver,
/// Preset Position, the move's start) and the last line at the target with Move_Complete.
#[test]
fn a_relative_move_prints_its_status_changes() {
    let script = Script::parse(RELATIVE, "relative.smd").unwrap();
    let trace = run(&script, &Options::default(), std::time::Instant::now());
    assert_eq!(
        header(&trace),
        "# relative.smd: incremental encoder, cycle 1ms, 0 to 1s\n  \
         time [s]  Motor_Position  Encoder_Position  Trapped_Encoder_Position  speed [steps/s]  \
         STATUS_word0  STATUS_word1  bits"
    );
    let got = lines(&trace);
    let expected_start = [
        // Power-up.
        "     0.000               0                 0                         0              0.0        0x4408        0x0000  Stopped Position_Invalid",
        // Enable_Driver.
        "     0.001               0                 0                         0              0.0        0x4408        0x8000  Stopped Position_Invalid | Drive_Is_Enabled",
        // Preset Position: the position becomes valid, Command_Acknowledge while the bit stays 1.
        "     0.011               0                 0                         0              0.0        0x4008        0xa000  Stopped | Command_Acknowledge Drive_Is_Enabled",
        "     0.021               0                 0                         0              0.0        0x4008        0x8000  Stopped | Drive_Is_Enabled",
        // The Relative Move starts: one cycle's acceleration from the starting speed 141.
        "     0.031               0                 0                         0            241.0        0x4021        0x8000  Moving_CW Accelerating | Drive_Is_Enabled",
        // At speed.
        "     0.129             504                 0                         0          10000.0        0x4001        0x8000  Moving_CW | Drive_Is_Enabled",
        // The deceleration.
        "     0.529            4504                 0                         0           9961.0        0x4041        0x8800  Moving_CW Decelerating | Drive_Is_Enabled",
        // On target.
        "     0.628            5000                 0                         0              0.0        0x4088        0x8800  Stopped Move_Complete | Drive_Is_Enabled",
    ];
    assert_eq!(got[..expected_start.len()], expected_start, "{got:#?}");
    assert_eq!(
        got.last().unwrap(),
        "     1.000            5000                 0                         0              0.0        0x4088        0x8000  Stopped Move_Complete | Drive_Is_Enabled"
    );
    assert_eq!(got.len(), expected_start.len() + 1);
    let last = trace.lines.last().unwrap();
    assert_eq!(last.time, Duration::from_secs(1));
    assert_eq!(last.inputs.motor_position, 5000);
    assert_ne!(last.inputs.status0 & stat0::MOVE_COMPLETE, 0);
}

/// `--every` adds lines at its multiples; the heartbeat alone never makes a line.
#[test]
fn every_adds_lines_at_an_interval() {
    let script = Script::parse(RELATIVE, "relative.smd").unwrap();
    let plain = run(&script, &Options::default(), std::time::Instant::now());
    let every = run(
        &script,
        &Options {
            every: Some(Duration::from_millis(250)),
        },
        std::time::Instant::now(),
    );
    let times: Vec<u128> = every.lines.iter().map(|s| s.time.as_millis()).collect();
    assert_eq!(
        times,
        [0, 1, 11, 21, 31, 129, 250, 500, 529, 628, 750, 1000]
    );
    assert_eq!(
        format_line(&every, &every.lines[6]),
        "     0.250            1714                 0                         0          10000.0        0x4001        0x8000  Moving_CW | Drive_Is_Enabled"
    );
    assert!(every.lines.len() > plain.lines.len());
}

/// Input 1 as E-Stop (CFG_Word_0 = 5): current into it during a move stops the motor at once with
/// Input_Error and Position_Invalid; Reset Errors clears Input_Error, the position stays invalid.
#[test]
fn an_e_stop_input_stops_the_move() {
    let source = "\
config cfg_word_0 5        # Input 1: E-Stop
at 0ms   out cmd1=0x8000 velocity=10000 acceleration=100 deceleration=100
at 10ms  out cmd0=0x0200
at 20ms  out cmd0=0
at 30ms  out cmd0=0x0002 position=5000
at 40ms  out cmd0=0
at 200ms input 1 on
at 250ms input 1 off
at 300ms out cmd0=0x0400   # Reset Errors
at 310ms out cmd0=0
until 400ms
";
    let script = Script::parse(source, "e-stop.smd").unwrap();
    assert_eq!(script.config.cfg0, 5);
    let trace = run(&script, &Options::default(), std::time::Instant::now());
    let got = lines(&trace);
    assert_eq!(
        got[5..],
        [
            "     0.129             504                 0                         0          10000.0        0x4001        0x8000  Moving_CW | Drive_Is_Enabled",
            "     0.201            1214                 0                         0              0.0        0x4c08        0x8001  Stopped Position_Invalid Input_Error | IN1_Active Drive_Is_Enabled",
            "     0.251            1214                 0                         0              0.0        0x4c08        0x8000  Stopped Position_Invalid Input_Error | Drive_Is_Enabled",
            "     0.301            1214                 0                         0              0.0        0x4408        0xa000  Stopped Position_Invalid | Command_Acknowledge Drive_Is_Enabled",
            "     0.311            1214                 0                         0              0.0        0x4408        0x8000  Stopped Position_Invalid | Drive_Is_Enabled",
            "     0.400            1214                 0                         0              0.0        0x4408        0x8000  Stopped Position_Invalid | Drive_Is_Enabled",
        ],
        "{got:#?}"
    );
}

/// An SDO write during the run (`at TIME config`) invalidates the position; an invalid value shows as
/// Configuration_Error and takes Drive_Is_Enabled away.
#[test]
fn config_writes_at_a_time() {
    let source = "\
at 0ms  out cmd1=0x8000
at 5ms  out cmd0=0x0200
at 6ms  out cmd0=0
at 10ms config motor_current 0
at 20ms config 8010:07 10
until 30ms
";
    let trace = run(
        &Script::parse(source, "sdo.smd").unwrap(),
        &Options::default(),
        std::time::Instant::now(),
    );
    let got = lines(&trace);
    assert_eq!(
        got[4..],
        [
            "     0.011               0                 0                         0              0.0        0x6408        0x0000  Stopped Position_Invalid Configuration_Error",
            "     0.021               0                 0                         0              0.0        0x4408        0x8000  Stopped Position_Invalid | Drive_Is_Enabled",
            "     0.030               0                 0                         0              0.0        0x4408        0x8000  Stopped Position_Invalid | Drive_Is_Enabled",
        ],
        "{got:#?}"
    );
}

/// A short cycle gives more decimals; a preset at rest makes a line of its own.
#[test]
fn a_short_cycle_and_a_preset_at_rest() {
    let source = "\
cycle 250us
at 0ms     out cmd1=0x8000 position=100
at 0.5ms   out cmd0=0x0200
at 0.75ms  out cmd0=0
at 1ms     out cmd0=0x0200 position=-7
until 1.5ms
";
    let trace = run(
        &Script::parse(source, "short.smd").unwrap(),
        &Options::default(),
        std::time::Instant::now(),
    );
    assert_eq!(
        lines(&trace),
        [
            "   0.00000               0                 0                         0              0.0        0x4408        0x0000  Stopped Position_Invalid",
            "   0.00025               0                 0                         0              0.0        0x4408        0x8000  Stopped Position_Invalid | Drive_Is_Enabled",
            "   0.00075             100                 0                         0              0.0        0x4008        0xa000  Stopped | Command_Acknowledge Drive_Is_Enabled",
            "   0.00100             100                 0                         0              0.0        0x4008        0x8000  Stopped | Drive_Is_Enabled",
            "   0.00125              -7                 0                         0              0.0        0x4008        0xa000  Stopped | Command_Acknowledge Drive_Is_Enabled",
            "   0.00150              -7                 0                         0              0.0        0x4008        0xa000  Stopped | Command_Acknowledge Drive_Is_Enabled",
        ]
    );
}

/// `--plot`: an SVG chart with its axis labels and the motion-bit strip; the table is still printed.
#[test]
fn plot_draws_an_svg_chart() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("move.svg");
    let script = examples().join("relative-move.smd");
    let (code, out, err) = smd(&[
        "simulate",
        script.to_str().unwrap(),
        "--plot",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("Stopped Move_Complete | Drive_Is_Enabled"),
        "{out}"
    );
    assert!(
        out.ends_with(&format!("# chart written to {}\n", svg.display())),
        "{out}"
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg"), "{}", &text[..100.min(text.len())]);
    for label in [
        "time [s]",
        "Motor_Position [steps]",
        "speed [steps/s]",
        "Moving_CW",
        "Accelerating",
        "Decelerating",
        "Move_Complete",
    ] {
        assert!(text.contains(label), "{label} missing");
    }
    assert!(text.contains("<polyline"), "no curve");
    assert!(text.contains("<rect"), "no bits");
}

/// Every example script runs through the binary with exit 0 and ends with its `until` line.
#[test]
fn the_example_scripts_run() {
    let mut scripts: Vec<PathBuf> = std::fs::read_dir(examples())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "smd"))
        .collect();
    scripts.sort();
    assert!(scripts.len() >= 2, "{scripts:?}");
    for script in &scripts {
        let (code, out, err) = smd(&["simulate", script.to_str().unwrap(), "--every", "100"]);
        assert_eq!(code, 0, "{}: {err}", script.display());
        assert!(err.is_empty(), "{err}");
        assert!(
            out.starts_with(&format!("# {}: ", script.display())),
            "{out}"
        );
        assert!(out.lines().count() > 4, "{out}");
    }
    let (_, out, _) = smd(&[
        "simulate",
        examples().join("jog-with-stop-input.smd").to_str().unwrap(),
    ]);
    // The Stop Jog input captured the encoder and stopped the jog.
    let stop = "     1.001           12064             12353                     12345           7960.0        \
                0x4041        0x8001  Moving_CW Decelerating | IN1_Active Drive_Is_Enabled";
    assert!(out.lines().any(|l| l == stop), "{out}");
    assert!(
        out.trim_end()
            .ends_with("Stopped Move_Complete | Drive_Is_Enabled"),
        "{out}"
    );
}

/// Errors exit 2 with `smd: <message>`.
#[test]
fn errors_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.smd");
    std::fs::write(&bad, "at 0ms out cmd0=1\nat 1ms out veloc=3\nuntil 1s\n").unwrap();
    let (code, out, err) = smd(&["simulate", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert_eq!(out, "");
    assert_eq!(
        err,
        format!(
            "smd: {}:2: unknown output field \"veloc\" (expected cmd0, cmd1, position, velocity, \
             acceleration, deceleration, motor_current or jerk)\n",
            bad.display()
        )
    );

    let missing = dir.path().join("missing.smd");
    let (code, _, err) = smd(&["simulate", missing.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.starts_with(&format!("smd: cannot read {}: ", missing.display())),
        "{err}"
    );

    // A device or a FIFO is refused before it is read or opened.
    let fifo = dir.path().join("fifo.smd");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    for path in [fifo.to_str().unwrap(), "/dev/zero"] {
        let (code, _, err) = smd(&["simulate", path]);
        assert_eq!(code, 2, "{path}");
        assert_eq!(
            err.trim(),
            format!("smd: cannot read {path}: not a regular file")
        );
    }

    let good = examples().join("relative-move.smd");
    let (code, _, err) = smd(&["simulate", good.to_str().unwrap(), "--every", "1.5"]);
    assert_eq!(code, 2);
    assert_eq!(
        err,
        format!(
            "smd: --every 1.5ms is not a whole number of cycles of {} (the cycle is 1ms)\n",
            good.display()
        )
    );
    let (code, _, err) = smd(&["simulate", good.to_str().unwrap(), "--every", "0"]);
    assert_eq!(code, 2);
    assert!(err.contains("is not an interval"), "{err}");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(512))]
    /// Any text is parsed without a panic: a script or an error naming a line of the file.
    #[test]
    fn any_script_text_parses_or_names_its_line(
        lines in proptest::collection::vec(
            proptest::prop_oneof![
                proptest::string::string_regex("[a-z0-9_:=. #-]{0,40}").unwrap(),
                proptest::string::string_regex("(at|until|config|cycle|unit) [a-z0-9_:=. x-]{0,30}").unwrap(),
                proptest::string::string_regex("at [0-9]{1,4}(ms|s|us) (out|input|config) [a-z0-9_=x -]{0,30}").unwrap(),
            ],
            0..12,
        ),
    ) {
        let text = lines.join("\n");
        match Script::parse(&text, "fuzz.smd") {
            Ok(script) => {
                // A script that parses runs (bounded: at most one hour of simulated time at ≥ 250 µs).
                if script.until <= Duration::from_secs(2) {
                    let _ = run(&script, &Options::default(), std::time::Instant::now());
                }
            }
            Err(e) => proptest::prop_assert!(e.to_string().starts_with("fuzz.smd"), "{}", e),
        }
    }
}
