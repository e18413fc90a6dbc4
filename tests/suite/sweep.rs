//! Sweeps, the pure parts: specs and their errors, points and shards, hashes, metric paths and
//! the Pareto front (issue 19).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use proptest::prelude::*;
use udc_studio::core::sweep::hash::point_hash;
use udc_studio::core::sweep::summary::{ParetoPoint, pareto_front};
use udc_studio::core::sweep::{ParamValue, Points, Shard};
use udc_studio::io::error::SpecError;
use udc_studio::io::sweep::metrics::{matches, select_columns};
use udc_studio::io::sweep::{flatten_metrics, parse_spec};

const SPEC: &str = r#"
job = "analyze"
[base]
preset = "toled-150dpi"
[[axis]]
param = "pitch-um"
values = [168, 84]
[[axis]]
param = "tiling"
values = ["repeat", "random-4", "random-d4"]
[[axis]]
param = "seed"
range = { start = 10, stop = 13 }
"#;

#[test]
fn points_are_the_product_with_the_last_axis_fastest() {
    let spec = parse_spec(SPEC, true).unwrap();
    let points = Points::new(&spec).unwrap();
    assert_eq!(points.count(), 2 * 3 * 4);
    let mut seen = std::collections::HashSet::new();
    for i in 0..points.count() {
        let p: Vec<String> = points.point(i).iter().map(|v| v.to_arg()).collect();
        // Mixed radix: seed is the lowest digit, pitch the highest.
        assert_eq!(p[2], (10 + i % 4).to_string());
        assert_eq!(
            p[1],
            ["repeat", "random-4", "random-d4"][(i / 4 % 3) as usize]
        );
        assert_eq!(p[0], ["168", "84"][(i / 12) as usize]);
        assert!(seen.insert(p), "point {i} repeats another");
    }
}

#[test]
fn ranges_and_linspaces_generate_their_values() {
    let spec = parse_spec(
        r#"job = "analyze"
[[axis]]
param = "pitch-um"
range = { start = 40.0, stop = 41.0, step = 0.25 }
[[axis]]
param = "seed"
linspace = { start = 0, stop = 1, count = 3 }"#,
        true,
    )
    .unwrap();
    let points = Points::new(&spec).unwrap();
    let pitch: Vec<f64> = points.axis(0).iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(pitch, vec![40.0, 40.25, 40.5, 40.75, 41.0]);
    let lin: Vec<f64> = points.axis(1).iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(lin, vec![0.0, 0.5, 1.0]);
    // Whole-number ranges stay whole numbers (a seed must not become "3.0").
    let ints = parse_spec(
        "job = \"analyze\"\n[[axis]]\nparam = \"seed\"\nrange = { start = 0, stop = 4, step = 2 }",
        true,
    )
    .unwrap();
    let p = Points::new(&ints).unwrap();
    assert_eq!(
        p.axis(0).to_vec(),
        vec![ParamValue::Int(0), ParamValue::Int(2), ParamValue::Int(4)]
    );
}

#[test]
fn bad_specs_are_refused_naming_the_field() {
    let cases: [(&str, &str); 9] = [
        ("job = \"analyse\"", "job"),
        ("job = \"analyze\"\ntypo = 1", "typo"),
        (
            "job = \"analyze\"\n[[axis]]\nparam = \"seed\"\nrange = { start = 0, stop = 4, step = 0 }",
            "axis[0].range.step",
        ),
        (
            "job = \"analyze\"\n[[axis]]\nparam = \"seed\"\nrange = { start = 5, stop = 4 }",
            "axis[0].range.stop",
        ),
        (
            "job = \"analyze\"\n[[axis]]\nparam = \"pitch-um\"\nvalues = [nan]",
            "axis[0].values[0]",
        ),
        (
            "job = \"analyze\"\n[[axis]]\nparam = \"out\"\nvalues = [\"x\"]",
            "axis[0].param",
        ),
        (
            "job = \"analyze\"\n[[axis]]\nparam = \"seed\"\nvalues = [1]\n[[axis]]\nparam = \"seed\"\nvalues = [2]",
            "axis[1].param",
        ),
        (
            "job = \"analyze\"\n[base]\nseed = 1\n[[axis]]\nparam = \"seed\"\nvalues = [2]",
            "axis[0].param",
        ),
        (
            "job = \"analyze\"\n[[axis]]\nparam = \"seed\"\nvalues = []",
            "axis[0].values",
        ),
    ];
    for (text, field) in cases {
        let err = parse_spec(text, true).expect_err(text).to_string();
        assert!(
            err.contains(field),
            "{text:?}: `{err}` does not name {field}"
        );
    }
    // TOML syntax errors give the line.
    let err = parse_spec("job = \"analyze\"\n[[axis]\n", true).unwrap_err();
    assert!(matches!(err, SpecError::Toml(_)), "{err:?}");
    assert!(err.to_string().contains("line 2"), "{err}");
    // JSON works the same way; a well-formed spec that is no valid sweep is the core's error.
    let err = parse_spec(r#"{"job": "analyze", "axis": [{"param": "seed"}]}"#, false).unwrap_err();
    assert!(matches!(err, SpecError::Invalid(_)), "{err:?}");
    assert!(err.to_string().contains("exactly one of"), "{err}");
    let err = parse_spec(r#"{"job": "analyze", "axis": [{"param": 7}]}"#, false).unwrap_err();
    assert!(
        matches!(&err, SpecError::JsonField { field, .. } if field == "axis[0].param"),
        "{err:?}"
    );
}

#[test]
fn too_many_points_are_refused_before_anything_runs() {
    let mut text = String::from("job = \"analyze\"\n");
    for k in 0..5 {
        text.push_str(&format!(
            "[[axis]]\nparam = \"p{k}\"\nrange = {{ start = 0, stop = 999999 }}\n"
        ));
    }
    let err = parse_spec(&text, true).unwrap_err().to_string();
    assert!(err.contains("points"), "{err}");
}

#[test]
fn shards_partition_the_points() {
    for count in [1u64, 7, 24, 100] {
        for n in 1..=6u64 {
            let mut owner = vec![0u32; count as usize];
            let mut total = 0;
            for s in 0..n {
                let shard = Shard { index: s, count: n };
                let mine = (0..count).filter(|i| shard.contains(*i)).count() as u64;
                assert_eq!(mine, shard.len(count));
                total += mine;
                for i in (0..count).filter(|i| shard.contains(*i)) {
                    owner[i as usize] += 1;
                }
            }
            assert_eq!(total, count);
            assert!(owner.iter().all(|o| *o == 1));
        }
    }
    assert_eq!(
        "2/5".parse::<Shard>().unwrap(),
        Shard { index: 2, count: 5 }
    );
    for bad in ["5/5", "1/0", "x/2", "3", "-1/2"] {
        assert!(bad.parse::<Shard>().is_err(), "{bad}");
    }
}

#[test]
fn point_hashes_ignore_order_and_see_values() {
    let a = vec![
        ("tiling".to_string(), "repeat".to_string()),
        ("seed".to_string(), "1".to_string()),
    ];
    let mut b = a.clone();
    b.reverse();
    assert_eq!(point_hash("analyze", &a), point_hash("analyze", &b));
    let mut c = a.clone();
    c[1].1 = "2".into();
    assert_ne!(point_hash("analyze", &a), point_hash("analyze", &c));
    assert_ne!(point_hash("analyze", &a), point_hash("restore", &a));
    assert_eq!(point_hash("analyze", &a).len(), 32);
}

#[test]
fn metrics_are_json_paths_with_named_list_items() {
    let v = serde_json::json!({
        "ltr": 0.25,
        "name": "x",
        "channels": [{"name": "R", "auc": 1.0, "curve": [1.0, 2.0]}, {"name": "G", "auc": 2.0}],
        "runs": [{"psnr_db": 20.0}],
    });
    let flat = flatten_metrics(&v);
    let names: Vec<&str> = flat.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        ["channels.R.auc", "channels.G.auc", "ltr", "runs.0.psnr_db"]
    );
    assert!(matches("channels.*.auc", "channels.G.auc"));
    assert!(!matches("channels.*", "channels.G.auc"));
    let cols = select_columns(&["runs.0.psnr_db".into(), "channels.*.auc".into()], &flat).unwrap();
    assert_eq!(cols, ["runs.0.psnr_db", "channels.R.auc", "channels.G.auc"]);
    let err = select_columns(&["auc".into()], &flat).unwrap_err();
    assert!(
        matches!(&err, SpecError::UnknownMetric { pattern, available }
            if pattern == "auc" && available.len() == 4),
        "{err:?}"
    );
    assert!(
        err.to_string().contains("ltr"),
        "the error lists what exists: {err}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn the_pareto_front_is_exactly_the_undominated_points(
        pts in prop::collection::vec((0u8..20, 0u8..20), 1..60),
        smaller in any::<bool>(),
    ) {
        let points: Vec<ParetoPoint> = pts
            .iter()
            .enumerate()
            .map(|(i, (x, y))| ParetoPoint { x: f64::from(*x), y: f64::from(*y), point: i as u64 })
            .collect();
        let s = if smaller { -1.0 } else { 1.0 };
        let dominates = |a: &ParetoPoint, b: &ParetoPoint| {
            s * a.x >= s * b.x && a.y >= b.y && (s * a.x > s * b.x || a.y > b.y)
        };
        let front = pareto_front(&points, smaller);
        for f in &front {
            prop_assert!(!points.iter().any(|p| dominates(p, f)), "{f:?} is dominated");
        }
        for p in &points {
            let on = front.iter().any(|f| f.x == p.x && f.y == p.y);
            let beaten = front.iter().any(|f| dominates(f, p));
            prop_assert!(on || beaten, "{p:?} is neither on the front nor beaten by it");
        }
        prop_assert!(front.windows(2).all(|w| w[0].x <= w[1].x));
    }
}
