//! The `serde` feature: configurations round-trip through JSON, and
//! deserialising validates again, so a bad file is an error, never a bad
//! sampler.
#![cfg(feature = "serde")]

use bridson::{
    Candidates, DEFAULT_ATTEMPTS, DEFAULT_MAX_GRID_BYTES, DEFAULT_MAX_WINDOW_BYTES, Domain, Error,
    GridLayout, PoissonDisk, PoissonDisk2, PoissonDiskBuilder, Scheme, Tiled, TiledBuilder,
};
use serde_json::{Value, json};

fn sampler_2d() -> PoissonDisk2 {
    let domain = Domain::new([-1.5, 0.25], [2.0, 3.0])
        .expect("valid box")
        .with_periodic([true, false]);
    PoissonDisk2::builder(domain, 0.125)
        .attempts(12)
        .layout(GridLayout::Sparse)
        .max_grid_bytes(1 << 24)
        .max_points(500)
        .candidates(Candidates::Sphere)
        .build()
        .expect("valid sampler")
}

/// Deserialises `value` as `T`, expecting failure; returns the message.
fn error_of<T: serde::de::DeserializeOwned + core::fmt::Debug>(value: &Value) -> String {
    let text = value.to_string();
    match serde_json::from_str::<T>(&text) {
        Ok(t) => panic!("{text} was accepted as {t:?}"),
        Err(e) => e.to_string(),
    }
}

fn assert_mentions(message: &str, words: &[&str]) {
    for word in words {
        assert!(
            message.contains(word),
            "error message {message:?} does not mention {word:?}"
        );
    }
}

// ---------------------------------------------------------------- round trips

#[test]
fn poisson_disk_2d_round_trips() {
    let sampler = sampler_2d();
    let text = serde_json::to_string(&sampler).expect("serialises");
    let back: PoissonDisk2 = serde_json::from_str(&text).expect("deserialises");
    assert_eq!(back, sampler, "round trip through {text}");
    assert_eq!(
        back.generate_seeded(3).unwrap(),
        sampler.generate_seeded(3).unwrap(),
        "same configuration, same points"
    );
    // The text is the documented configuration, nothing internal.
    let value: Value = serde_json::from_str(&text).expect("valid JSON");
    assert_eq!(
        value,
        json!({
            "domain": {"lo": [-1.5, 0.25], "hi": [2.0, 3.0], "periodic": [true, false]},
            "radius": 0.125,
            "attempts": 12,
            "candidates": "sphere",
            "layout": "sparse",
            "max_grid_bytes": 1 << 24,
            "max_points": 500,
        }),
        "serialised form"
    );
}

#[test]
fn poisson_disk_defaults_round_trip() {
    let sampler = PoissonDisk::<3>::new(Domain::from_extent([1.0; 3]).expect("box"), 0.2)
        .expect("valid sampler");
    let text = serde_json::to_string_pretty(&sampler).expect("serialises");
    let back: PoissonDisk<3> = serde_json::from_str(&text).expect("deserialises");
    assert_eq!(back, sampler, "round trip through {text}");
}

#[test]
fn builder_round_trips_and_matches_the_sampler_form() {
    let sampler = sampler_2d();
    let builder = sampler.to_builder();
    let text = serde_json::to_string(&builder).expect("serialises");
    assert_eq!(
        text,
        serde_json::to_string(&sampler).expect("serialises"),
        "a sampler is serialised as its settings"
    );
    let back: PoissonDiskBuilder<2> = serde_json::from_str(&text).expect("deserialises");
    assert_eq!(back, builder, "round trip through {text}");
    assert_eq!(back.build(), Ok(sampler), "rebuilds the same sampler");
}

/// A `PoissonDiskBuilder` is the unchecked form: it reads settings that `build` (and
/// deserialising a `PoissonDisk`) then rejects. Its domain is still checked.
#[test]
fn builder_defers_validation_to_build() {
    let bad_radius = with_field("radius", json!(-1.0));
    let builder: PoissonDiskBuilder<2> =
        serde_json::from_value(bad_radius).expect("read unchecked");
    assert_eq!(
        builder.build(),
        Err(Error::InvalidRadius),
        "checked by build"
    );
    let zero_k = with_field("attempts", json!(0));
    let builder: PoissonDiskBuilder<2> = serde_json::from_value(zero_k).expect("read unchecked");
    assert_eq!(
        builder.build(),
        Err(Error::ZeroAttempts),
        "checked by build"
    );
    let empty = with_field(
        "domain",
        json!({"lo": [0.0, 1.0], "hi": [1.0, 1.0], "periodic": [false, false]}),
    );
    let message = match serde_json::from_value::<PoissonDiskBuilder<2>>(empty) {
        Ok(b) => panic!("an empty domain was read: {b:?}"),
        Err(e) => e.to_string(),
    };
    assert_mentions(&message, &["axis 1", "lo must be < hi"]);
}

#[test]
fn domain_3d_round_trips() {
    let domain = Domain::new([-1.0, 0.1 + 0.2, 2.5], [1.0, 3.0, 1e10])
        .expect("valid box")
        .with_periodic([true, false, true]);
    let text = serde_json::to_string(&domain).expect("serialises");
    let back: Domain<3> = serde_json::from_str(&text).expect("deserialises");
    assert_eq!(back, domain, "round trip through {text}");
    assert_eq!(
        back.lo()[1].to_bits(),
        (0.1f64 + 0.2).to_bits(),
        "bit-exact bound"
    );
}

/// Lower-case, as the `points` command line spells them
/// (`--candidates sphere`); the capitalised Rust names are not accepted.
#[test]
fn enums_are_lower_case_strings() {
    fn check<T>(cases: &[(T, &str)])
    where
        T: serde::Serialize + serde::de::DeserializeOwned + PartialEq + core::fmt::Debug + Copy,
    {
        for &(value, name) in cases {
            let quoted = format!("\"{name}\"");
            assert_eq!(
                serde_json::to_string(&value).expect("serialises"),
                quoted,
                "{value:?}"
            );
            assert_eq!(
                serde_json::from_str::<T>(&quoted).expect("deserialises"),
                value,
                "{name}"
            );
            let capitalised = format!("\"{}{}\"", name[..1].to_uppercase(), &name[1..]);
            assert!(
                serde_json::from_str::<T>(&capitalised).is_err(),
                "{capitalised} is not a value"
            );
        }
    }
    check(&[
        (Candidates::Annulus, "annulus"),
        (Candidates::Sphere, "sphere"),
    ]);
    check(&[
        (GridLayout::Auto, "auto"),
        (GridLayout::Dense, "dense"),
        (GridLayout::Sparse, "sparse"),
        (GridLayout::Paged, "paged"),
    ]);
    check(&[(Scheme::Sweep, "sweep"), (Scheme::Paper, "paper")]);
    assert!(
        serde_json::from_str::<Candidates>("\"disk\"").is_err(),
        "unknown variant"
    );
}

// ---------------------------------------------------------------- defaults

#[test]
fn missing_optional_fields_get_defaults() {
    let minimal = json!({
        "domain": {"lo": [0.0, 0.0], "hi": [1.0, 2.0], "periodic": [false, true]},
        "radius": 0.05,
    });
    let sampler: PoissonDisk2 = serde_json::from_value(minimal).expect("deserialises");
    assert_eq!(sampler.attempts(), DEFAULT_ATTEMPTS, "attempts");
    assert_eq!(sampler.attempts(), 30, "Bridson's k");
    assert_eq!(sampler.candidates(), Candidates::Annulus, "candidates");
    assert_eq!(sampler.layout(), GridLayout::Auto, "layout");
    assert_eq!(
        sampler.max_grid_bytes(),
        DEFAULT_MAX_GRID_BYTES,
        "max_grid_bytes"
    );
    assert_eq!(sampler.max_points(), None, "max_points");
    let built = PoissonDisk2::new(
        Domain::from_extent([1.0, 2.0])
            .expect("box")
            .with_periodic([false, true]),
        0.05,
    )
    .expect("valid");
    assert_eq!(sampler, built, "same as PoissonDisk::new");
}

#[test]
fn periodic_defaults_to_all_bounded() {
    let domain: Domain<3> =
        serde_json::from_value(json!({"lo": [0.0, 0.0, 0.0], "hi": [1.0, 2.0, 3.0]}))
            .expect("deserialises");
    assert_eq!(
        domain,
        Domain::from_extent([1.0, 2.0, 3.0]).expect("box"),
        "as Domain::new"
    );
    let minimal = json!({"domain": {"lo": [0.0, 0.0], "hi": [1.0, 1.0]}, "radius": 0.1});
    let sampler: PoissonDisk2 = serde_json::from_value(minimal).expect("deserialises");
    assert_eq!(sampler.domain().periodic(), [false; 2], "nested");
}

/// A misspelt field is an error naming it, never silently ignored
/// (`"atempts": 5` once gave `k = 30`).
#[test]
fn unknown_fields_are_rejected() {
    let misspelt = with_field("atempts", json!(5));
    for message in [
        error_of::<PoissonDisk2>(&misspelt),
        error_of::<PoissonDiskBuilder<2>>(&misspelt),
    ] {
        assert_mentions(&message, &["unknown field", "atempts"]);
    }
    let domain = json!({"lo": [0.0], "hi": [1.0], "periodc": [true]});
    assert_mentions(
        &error_of::<Domain<1>>(&domain),
        &["unknown field", "periodc"],
    );
    assert_mentions(
        &error_of::<PoissonDisk<1>>(&json!({"domain": domain, "radius": 0.1})),
        &["unknown field", "periodc"],
    );
    // Internal state is not a field either.
    assert_mentions(
        &error_of::<PoissonDisk2>(&with_field("negative_cap", json!(true))),
        &["unknown field", "negative_cap"],
    );
    let tiled = json!({"width": 4, "height": 3, "per_pixel": 2.0, "sheme": "paper"});
    for message in [error_of::<Tiled>(&tiled), error_of::<TiledBuilder>(&tiled)] {
        assert_mentions(&message, &["unknown field", "sheme"]);
    }
}

#[test]
fn required_fields_are_required() {
    let no_radius = json!({
        "domain": {"lo": [0.0, 0.0], "hi": [1.0, 1.0], "periodic": [false, false]},
    });
    assert_mentions(&error_of::<PoissonDisk2>(&no_radius), &["radius"]);
    let no_domain = json!({ "radius": 0.1 });
    assert_mentions(&error_of::<PoissonDisk2>(&no_domain), &["domain"]);
    let no_hi = json!({"lo": [0.0, 0.0], "periodic": [false, false]});
    assert_mentions(&error_of::<Domain<2>>(&no_hi), &["hi"]);
}

// ---------------------------------------------------------------- validation

fn with_field(key: &str, value: Value) -> Value {
    let mut v = json!({
        "domain": {"lo": [0.0, 0.0], "hi": [1.0, 1.0], "periodic": [false, false]},
        "radius": 0.1,
    });
    v[key] = value;
    v
}

#[test]
fn negative_radius_is_rejected() {
    let message = error_of::<PoissonDisk2>(&with_field("radius", json!(-1.0)));
    assert_mentions(&message, &["radius", "> 0"]);
    let message = error_of::<PoissonDisk2>(&with_field("radius", json!(0.0)));
    assert_mentions(&message, &["radius"]);
    let message = error_of::<PoissonDisk2>(&with_field("radius", json!(1e-200)));
    assert_mentions(&message, &["radius"]);
}

#[test]
fn empty_box_is_rejected() {
    let equal = json!({"lo": [0.0, 1.0], "hi": [1.0, 1.0], "periodic": [false, false]});
    assert_mentions(
        &error_of::<Domain<2>>(&equal),
        &["axis 1", "lo must be < hi"],
    );
    let reversed = json!({"lo": [2.0, 0.0], "hi": [1.0, 1.0], "periodic": [false, false]});
    assert_mentions(
        &error_of::<Domain<2>>(&reversed),
        &["axis 0", "lo must be < hi"],
    );
    // Nested in a sampler too.
    assert_mentions(
        &error_of::<PoissonDisk2>(&with_field("domain", reversed)),
        &["axis 0", "lo must be < hi"],
    );
}

#[test]
fn overflowing_extent_is_rejected() {
    let huge = json!({"lo": [-1e308], "hi": [1e308], "periodic": [false]});
    assert_mentions(&error_of::<Domain<1>>(&huge), &["axis 0", "overflow"]);
}

#[test]
fn zero_dimension_is_rejected() {
    let empty = json!({"lo": [], "hi": [], "periodic": []});
    assert_mentions(&error_of::<Domain<0>>(&empty), &["dimension"]);
}

#[test]
fn zero_attempts_is_rejected() {
    let message = error_of::<PoissonDisk2>(&with_field("attempts", json!(0)));
    assert_mentions(&message, &["attempts", "at least 1"]);
}

#[test]
fn wrong_array_length_is_rejected() {
    for (field, bad) in [
        ("lo", json!([0.0, 0.0, 0.0])),
        ("lo", json!([0.0])),
        ("hi", json!([])),
        ("periodic", json!([true, false, true])),
        ("periodic", json!([true])),
    ] {
        let mut domain = json!({"lo": [0.0, 0.0], "hi": [1.0, 1.0], "periodic": [false, false]});
        domain[field] = bad.clone();
        let message = error_of::<Domain<2>>(&domain);
        assert_mentions(&message, &["invalid length", "array of 2 elements"]);
        let message = error_of::<PoissonDisk2>(&with_field("domain", domain));
        assert_mentions(&message, &["invalid length", "array of 2 elements"]);
    }
}

#[test]
fn grid_over_budget_is_rejected() {
    let dense_small_budget = with_field("layout", json!("dense"));
    let mut v = dense_small_budget;
    v["radius"] = json!(0.001);
    v["max_grid_bytes"] = json!(1000);
    assert_mentions(&error_of::<PoissonDisk2>(&v), &["budget of 1000 bytes"]);
    let huge = with_field(
        "domain",
        json!({"lo": [0.0, 0.0], "hi": [1e6, 1e6], "periodic": [false, false]}),
    );
    let mut tiny_r = huge;
    tiny_r["radius"] = json!(1e-3);
    tiny_r["layout"] = json!("dense");
    assert_mentions(&error_of::<PoissonDisk2>(&tiny_r), &["budget"]);
}

#[test]
fn wrong_types_are_rejected() {
    assert!(
        serde_json::from_value::<PoissonDisk2>(with_field("radius", json!("0.1"))).is_err(),
        "radius as a string"
    );
    assert!(
        serde_json::from_value::<PoissonDisk2>(with_field("attempts", json!(-3))).is_err(),
        "negative attempts"
    );
    assert!(
        serde_json::from_value::<PoissonDisk2>(with_field("candidates", json!("disk"))).is_err(),
        "unknown candidates"
    );
}

// ---------------------------------------------------------------- Tiled

/// Streams the first `pixels` pixels of `tiled` for `seed`.
fn first_pixels(tiled: &Tiled, seed: u64, pixels: usize) -> Vec<bridson::Pixel> {
    tiled.pixels_seeded(seed).take(pixels).collect()
}

#[test]
fn tiled_round_trips_with_each_spacing() {
    let builders = [
        Tiled::builder(5, 4).radius(0.3).attempts(12),
        Tiled::builder(5, 4)
            .per_pixel(3.5)
            .candidates(Candidates::Sphere)
            .scheme(Scheme::Paper),
        Tiled::builder(5, 4).exact(2).max_window_bytes(1 << 20),
        Tiled::builder(5, 4).per_pixel(2.0).exact(3),
    ];
    for builder in builders {
        let tiled = builder.build().expect("valid");
        let text = serde_json::to_string(&tiled).expect("serialises");
        let back: Tiled = serde_json::from_str(&text).expect("deserialises");
        assert_eq!(back, tiled, "round trip through {text}");
        assert_eq!(
            first_pixels(&back, 9, 7),
            first_pixels(&tiled, 9, 7),
            "{text}: same configuration, same points"
        );
        let as_builder = serde_json::to_string(&builder).expect("serialises");
        assert_eq!(as_builder, text, "a Tiled is written as its settings");
        let read: TiledBuilder = serde_json::from_str(&text).expect("deserialises");
        assert_eq!(read, builder, "builder round trip through {text}");
        assert_eq!(tiled.to_builder(), builder, "to_builder");
    }
}

#[test]
fn tiled_serialised_form_is_the_documented_one() {
    let tiled = Tiled::builder(64, 48)
        .per_pixel(4.0)
        .candidates(Candidates::Sphere)
        .build()
        .expect("valid");
    assert_eq!(
        serde_json::to_value(tiled).expect("serialises"),
        json!({
            "width": 64,
            "height": 48,
            "radius": null,
            "per_pixel": 4.0,
            "exact": null,
            "exact_method": "eliminate",
            "exact_oversample": 1.16,
            "exact_edge_bias": null,
            "attempts": null,
            "candidates": "sphere",
            "scheme": "sweep",
            "max_window_bytes": DEFAULT_MAX_WINDOW_BYTES,
        }),
        "serialised form"
    );
    let minimal: Tiled =
        serde_json::from_value(json!({"width": 64, "height": 48, "per_pixel": 4.0}))
            .expect("deserialises");
    assert_eq!(
        minimal,
        Tiled::builder(64, 48)
            .per_pixel(4.0)
            .build()
            .expect("valid"),
        "absent fields take the builder's defaults"
    );
}

/// Deserialising a `Tiled` runs `build`; a `TiledBuilder` is read
/// unchecked, except for a spacing given twice, which it cannot hold.
#[test]
fn tiled_is_validated_on_deserialise() {
    let cases = [
        (
            json!({"width": 0, "height": 3, "radius": 0.5}),
            Error::EmptyRaster { axis: 0 },
        ),
        (
            json!({"width": 3, "height": 0, "radius": 0.5}),
            Error::EmptyRaster { axis: 1 },
        ),
        (
            json!({"width": 3, "height": 3, "per_pixel": -1.0}),
            Error::InvalidPerPixel,
        ),
        (
            json!({"width": 3, "height": 3, "exact": 0}),
            Error::InvalidPerPixel,
        ),
        (
            json!({"width": 3, "height": 3, "radius": -0.5}),
            Error::InvalidRadius,
        ),
        (json!({"width": 3, "height": 3}), Error::InvalidRadius),
        (
            json!({"width": 3, "height": 3, "radius": 0.5, "attempts": 0}),
            Error::ZeroAttempts,
        ),
        (
            json!({"width": 3, "height": 3, "radius": 0.5, "max_window_bytes": 10}),
            Tiled::builder(3, 3)
                .radius(0.5)
                .max_window_bytes(10)
                .build()
                .expect_err("over budget"),
        ),
    ];
    for (value, error) in cases {
        let message = error_of::<Tiled>(&value);
        assert_eq!(message, error.to_string(), "{value}");
        let builder: TiledBuilder = serde_json::from_value(value.clone()).expect("unchecked");
        assert_eq!(builder.build(), Err(error), "{value}: checked by build");
    }
    let both = json!({"width": 3, "height": 3, "radius": 0.5, "per_pixel": 2.0});
    for message in [error_of::<Tiled>(&both), error_of::<TiledBuilder>(&both)] {
        assert_mentions(&message, &["radius", "per_pixel", "not both"]);
    }
    let no_height = json!({"width": 3, "radius": 0.5});
    assert_mentions(&error_of::<Tiled>(&no_height), &["height"]);
}

// ---------------------------------------------------------------- count mode

/// Count mode is written as `about_points`; `radius` may then be left out,
/// and a sampler read back derives the same radius.
#[test]
fn count_mode_round_trips() {
    let domain = Domain::from_extent([2.0, 1.0]).expect("box");
    let builder = PoissonDisk2::about_points_builder(domain, 800).candidates(Candidates::Sphere);
    assert_eq!(
        serde_json::to_value(builder).expect("serialises"),
        json!({
            "domain": {"lo": [0.0, 0.0], "hi": [2.0, 1.0], "periodic": [false, false]},
            "about_points": 800,
            "attempts": 30,
            "candidates": "sphere",
            "layout": "auto",
            "max_grid_bytes": DEFAULT_MAX_GRID_BYTES,
            "max_points": null,
        }),
        "an unbuilt builder has no radius"
    );
    let sampler = builder.build().expect("valid");
    let text = serde_json::to_string(&sampler).expect("serialises");
    let back: PoissonDisk2 = serde_json::from_str(&text).expect("deserialises");
    assert_eq!(back, sampler, "round trip through {text}");
    assert_eq!(back.requested_count(), Some(800), "count kept");
    let minimal: PoissonDisk2 = serde_json::from_value(json!({
        "domain": {"lo": [0.0, 0.0], "hi": [2.0, 1.0]},
        "about_points": 800,
        "candidates": "sphere",
    }))
    .expect("deserialises");
    assert_eq!(minimal, sampler, "no radius needed");
    assert_mentions(
        &error_of::<PoissonDisk2>(&with_field("about_points", json!(0))),
        &["count"],
    );
}
