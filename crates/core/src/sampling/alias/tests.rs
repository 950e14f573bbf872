use super::*;

fn powers(values: &[f64]) -> LightPowers {
    LightPowers::new(values.to_vec()).unwrap()
}

fn exact(values: &[f64]) -> AliasTable {
    AliasTable::build_exact(&powers(values))
}

fn integer(values: &[f64]) -> AliasTable {
    AliasTable::build(&powers(values))
}

/// `|P(i) − p_i|` in units of `2^-32/N`, per light, for the integer table of `values`.
fn integer_errors_in_units(values: &[f64]) -> (AliasTable, Vec<f64>) {
    let table = integer(values);
    let p = powers(values).pmf();
    let n = values.len() as f64;
    let unit = 1.0 / (n * 4_294_967_296.0);
    let errors = table
        .implied_pmf_packed()
        .iter()
        .zip(&p)
        .map(|(got, want)| (got - want).abs() / unit)
        .collect();
    (table, errors)
}

#[test]
fn seed_table_is_exact() {
    let t = exact(&[2.0, 5.0, 20.0]);
    assert_eq!(t.thresholds(), &[6.0 / 27.0, 15.0 / 27.0, 1.0]);
    assert_eq!(t.aliases(), &[2, 2, 2]);
    assert_eq!(t.pmf_slice(), &[2.0 / 27.0, 5.0 / 27.0, 20.0 / 27.0]);
}

#[test]
fn seed_implied_pmf_matches() {
    let t = exact(&[2.0, 5.0, 20.0]);
    for (implied, want) in t.implied_pmf().iter().zip([2.0, 5.0, 20.0]) {
        assert!((implied - want / 27.0).abs() <= 1e-15, "{implied}");
    }
}

#[test]
fn seed_integer_table_has_the_seed_aliases_and_quantized_thresholds() {
    // m = round(N·2^32·p): 2/9, 5/9 and 20/9 of 2^32, summing to exactly 3·2^32.
    let t = integer(&[2.0, 5.0, 20.0]);
    assert_eq!(t.aliases(), &[2, 2, 2]);
    let c = 4_294_967_296.0f64;
    for (got, want) in t.thresholds().iter().zip([6.0 / 27.0, 15.0 / 27.0, 1.0]) {
        assert!((got - want).abs() <= 0.5 / c, "{got} vs {want}");
    }
    assert_eq!(t.packed_masses().iter().sum::<u64>(), 3 << 32);
    let (_, errors) = integer_errors_in_units(&[2.0, 5.0, 20.0]);
    assert!(errors.iter().all(|&e| e < 1.0), "{errors:?}");
}

#[test]
fn exhausted_large_column_never_gets_a_negative_threshold() {
    // Found by proptest in CI: a large column left with exactly 0 of its own mass
    // received a negative carried rounding error (threshold −4.5e-17 before the fix).
    let tiny = f64::from_bits(1);
    let mut values = vec![0.0; 95];
    for i in [9, 21, 39] {
        values[i] = tiny;
    }
    values[25] = 1.000_000_000_000_000_6e293;
    for i in [40, 41, 43, 44, 48, 53, 57, 67, 75, 78] {
        values[i] = f64::MAX;
    }
    let t = exact(&values);
    assert!(t.thresholds().iter().all(|&x| (0.0..=1.0).contains(&x)));
    let implied = t.implied_pmf();
    for (i, (&got, &want)) in implied.iter().zip(t.pmf_slice()).enumerate() {
        assert!(
            (got - want).abs() <= 1e-12 * want + 1e-15 / 95.0,
            "light {i}"
        );
    }
    // The integer table of the same powers: the tiny ones reachable, zeros never.
    let t = integer(&values);
    let masses = t.packed_masses();
    for (i, (&m, &p)) in masses.iter().zip(&values).enumerate() {
        assert_eq!(m > 0, p > 0.0, "light {i}: mass {m}, power {p}");
    }
}

#[test]
fn one_light_is_always_picked() {
    for t in [exact(&[3.5]), integer(&[3.5])] {
        assert_eq!(t.thresholds(), &[1.0]);
        assert_eq!(t.aliases(), &[0]);
        for r in [0, 1, u32::MAX / 2, u32::MAX] {
            assert_eq!(t.sample_u32(r, u32::MAX), 0);
            assert_eq!(t.sample_one_random(r), 0);
        }
    }
}

#[test]
fn zero_power_columns_always_alias_to_a_positive_light() {
    for t in [exact(&[0.0, 1.0, 0.0, 3.0]), integer(&[0.0, 1.0, 0.0, 3.0])] {
        for (i, e) in t.packed().iter().enumerate() {
            if i % 2 == 0 {
                assert_eq!(e.threshold, 0);
                assert_ne!(e.alias as usize % 2, 0);
            }
        }
    }
}

#[test]
fn multiply_high_reaches_every_column() {
    let t = integer(&[1.0; 5]);
    let first_r = |c: u64| (c << 32).div_ceil(5) as u32;
    for c in 0..5 {
        assert_eq!(t.column(first_r(c)), c as usize);
    }
    assert_eq!(t.column(u32::MAX), 4);
}

#[test]
fn integer_masses_sum_exactly_and_stay_within_one_unit() {
    let mut rng = Rng::new(5, 0);
    let sets: Vec<Vec<f64>> = vec![
        (1..=1000).map(f64::from).collect(),
        (0..4096).map(|_| -(1.0 - rng.next_unit()).ln()).collect(),
        (0..3000)
            .map(|_| 10f64.powf(60.0 * rng.next_unit() - 30.0))
            .collect(),
        vec![0.7; 10_007],
        vec![1.0; 1 << 12],
    ];
    for values in sets {
        let (t, errors) = integer_errors_in_units(&values);
        let n = values.len() as u64;
        assert_eq!(t.packed_masses().iter().sum::<u64>(), n << 32);
        let unit = 1.0 / (n as f64 * 4_294_967_296.0);
        let tiny = powers(&values).pmf().iter().any(|&p| p > 0.0 && p < unit);
        let mut aliased_to = vec![0usize; values.len()];
        for e in t.packed() {
            aliased_to[e.alias as usize] += 1;
        }
        for (i, &e) in errors.iter().enumerate() {
            // Within one unit; lights some flagged (tiny) columns alias to lose a unit each.
            let bound = if tiny {
                1.0 + aliased_to[i] as f64
            } else {
                1.0
            };
            assert!(e <= bound, "N = {n}: light {i} off by {e} units of 2^-32/N");
            assert!(tiny || e < 1.0, "N = {n}: light {i} off by {e}");
        }
    }
}

#[test]
fn tiny_positive_powers_take_a_unit_from_their_alias() {
    // p_i far below 2^-32/N: quantized to 0, flagged, threshold 1.
    let mut values = vec![1e-300; 50];
    values.extend([1.0, 2.0, 0.0]);
    let (t, errors) = integer_errors_in_units(&values);
    let masses = t.packed_masses();
    let mut aliased_to = vec![0usize; values.len()];
    for e in t.packed() {
        aliased_to[e.alias as usize] += 1;
    }
    for (i, &p) in values.iter().enumerate() {
        assert_eq!(masses[i] > 0, p > 0.0, "light {i}");
        assert!(
            errors[i] <= 1.0 + aliased_to[i] as f64,
            "light {i}: {} units, {} aliases",
            errors[i],
            aliased_to[i]
        );
    }
}

#[test]
fn rebuild_equals_build_and_reuses_the_buffers() {
    let a = powers(&(1..=4096).map(f64::from).collect::<Vec<_>>());
    let b = powers(
        &(1..=4096)
            .rev()
            .map(|i| f64::from(i).sqrt())
            .collect::<Vec<_>>(),
    );
    for construction in Construction::ALL {
        let mut table = AliasTable::build_with(&a, construction);
        table.rebuild(&a); // the first rebuild brings the sweep's bitmap back
        let words = table.words.as_ptr();
        let heavy = table.heavy.as_ptr();
        table.rebuild(&b);
        assert_eq!(
            table.heavy.as_ptr(),
            heavy,
            "{construction}: bitmap reallocated"
        );
        assert_eq!(
            table,
            AliasTable::build_with(&b, construction),
            "{construction}"
        );
        assert_eq!(table.words.as_ptr(), words, "{construction}: reallocated");
    }
}

#[test]
fn batch_picks_equal_one_at_a_time_picks() {
    // N = 10^6 rejects 2.25·10^-4 of the column draws: the batch crosses many rejections.
    let mut rng = Rng::new(3, 0);
    let values: Vec<f64> = (0..1_000_000).map(|_| rng.next_unit() + 0.01).collect();
    let table = integer(&values);
    for (stream, len) in [(0u64, 0usize), (1, 1), (2, 511), (3, 513), (4, 200_000)] {
        let mut one = Rng::new(11, stream);
        let expected: Vec<u32> = (0..len).map(|_| table.sample(&mut one)).collect();
        let mut batch_rng = Rng::new(11, stream);
        let mut got = vec![0u32; len];
        table.sample_into(&mut got, &mut batch_rng);
        assert_eq!(got, expected, "stream {stream}");
        assert_eq!(batch_rng, one, "stream {stream}: final state");
        // The portable instance of the block passes (the one run without AVX2) too.
        let mut portable_rng = Rng::new(11, stream);
        let mut portable = vec![0u32; len];
        table.sample_into_portable(&mut portable, &mut portable_rng);
        assert_eq!(portable, expected, "stream {stream}: portable passes");
        assert_eq!(portable_rng, one, "stream {stream}: portable final state");
    }
}

#[test]
fn the_avx2_and_portable_batch_passes_pick_alike() {
    // Where the processor has AVX2, `sample_into` runs the AVX2 instance; the portable one
    // must give the same picks on every size, rejections (N = 10^6 + 3) included.
    #[cfg(target_arch = "x86_64")]
    eprintln!(
        "AVX2 {}",
        if std::arch::is_x86_feature_detected!("avx2") {
            "present: comparing it with the portable passes"
        } else {
            "absent: both runs take the portable passes"
        }
    );
    let mut rng = Rng::new(4, 0);
    for n in [1usize, 3, 1000, 1_000_003] {
        let values: Vec<f64> = (0..n).map(|_| rng.next_unit() + 0.01).collect();
        let table = integer(&values);
        let (mut fastest_rng, mut portable_rng) = (Rng::new(12, n as u64), Rng::new(12, n as u64));
        let (mut fastest, mut portable) = (vec![0u32; 100_000], vec![0u32; 100_000]);
        table.sample_into(&mut fastest, &mut fastest_rng);
        table.sample_into_portable(&mut portable, &mut portable_rng);
        assert_eq!(fastest, portable, "N = {n}");
        assert_eq!(fastest_rng, portable_rng, "N = {n}: final state");
        assert!(fastest.iter().all(|&i| (i as usize) < n));
    }
}

#[test]
fn constructions_parse_and_name_themselves() {
    for c in Construction::ALL {
        assert_eq!(c.name().parse::<Construction>(), Ok(c));
    }
    assert!("fast".parse::<Construction>().is_err());
}

/// The division by multiplication that groups columns equals `/` for every divisor shape
/// (1, 2, odd, powers of two and their neighbours, up to `2^32 − 1`) at indices where it
/// could break: 0, each multiple of the divisor and its neighbours, and the top of `u32`.
#[test]
fn group_of_divides_as_the_hardware_does() {
    use super::GroupOf;
    let divisors: [u64; 14] = [
        1,
        2,
        3,
        7,
        16,
        48,
        15_259,
        65_535,
        65_536,
        65_537,
        (1 << 24) - 1,
        (1 << 31) + 1,
        u32::MAX as u64 - 1,
        u32::MAX as u64,
    ];
    for d in divisors {
        let g = GroupOf::new(d as usize);
        let mut probes: Vec<u64> = vec![0, 1, u32::MAX as u64 - 1, u32::MAX as u64];
        for k in [1u64, 2, 3, 1000, 65_535] {
            let m = k * d;
            probes.extend([m.saturating_sub(1), m, m + 1]);
        }
        for i in probes.into_iter().filter_map(|i| u32::try_from(i).ok()) {
            assert_eq!(g.index(i) as u64, u64::from(i) / d, "{i} / {d}");
        }
    }
}
