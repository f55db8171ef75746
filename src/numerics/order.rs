//! Sorting by a number, with one copy of the sort code; and grouping by a label in the order the
//! labels first appear ([`groups_in_order`]).
//!
//! Every `sort_by` with its own closure is a separate instance of the standard library's stable
//! sort (about 5 kB of wasm each); the stages sort by a floating-point key in many places, so
//! they sort through these functions, which instantiate it once for `f64` ([`sort_f64`]) and once
//! for an index array ordered by keys ([`argsort`]); the generic wrappers only gather keys and
//! move elements.
//!
//! The order is IEEE 754's total order (`f64::total_cmp`: −0 before +0, NaN after +∞), and
//! every sort is stable: elements with equal keys keep their order. A result is therefore the
//! one `v.sort_by(|a, b| key(a).total_cmp(&key(b)))` gives.
//!
//! ```
//! use testpiece::numerics::order::{argsort, argsort_descending, sort_by_key_f64};
//! let keys = [2.0, -1.0, 2.0, 0.5];
//! assert_eq!(argsort(&keys), vec![1, 3, 0, 2]);
//! // Largest first, equal keys still in their first order.
//! assert_eq!(argsort_descending(&keys), vec![0, 2, 3, 1]);
//! let mut v = vec![("a", 2.0), ("b", -1.0), ("c", 2.0)];
//! sort_by_key_f64(&mut v, |x| x.1);
//! assert_eq!(v, vec![("b", -1.0), ("a", 2.0), ("c", 2.0)]);
//! ```

/// Sorts `x` in ascending total order.
#[inline(never)]
pub fn sort_f64(x: &mut [f64]) {
    x.sort_by(f64::total_cmp);
}

/// Sorts `x` largest first (total order). Equal values are bit-identical, so this is the
/// ascending sort reversed.
pub fn sort_f64_descending(x: &mut [f64]) {
    sort_f64(x);
    x.reverse();
}

/// The indices `0..keys.len()` in ascending order of their keys, equal keys by index.
#[inline(never)]
pub fn argsort(keys: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..keys.len()).collect();
    order.sort_by(|&a, &b| keys[a].total_cmp(&keys[b]));
    order
}

/// The indices `0..keys.len()` largest key first, equal keys by index: the ascending order of
/// the negated keys (negation reverses the total order).
pub fn argsort_descending(keys: &[f64]) -> Vec<usize> {
    let negated: Vec<f64> = keys.iter().map(|k| -k).collect();
    argsort(&negated)
}

/// Puts `v` in the given order: afterwards `v[k]` is the element that was at `order[k]`.
/// `order` is a permutation of `0..v.len()`.
pub fn permute<T>(v: &mut Vec<T>, order: &[usize]) {
    debug_assert_eq!(order.len(), v.len());
    let mut slots: Vec<Option<T>> = v.drain(..).map(Some).collect();
    v.extend(
        order
            .iter()
            .filter_map(|&i| slots.get_mut(i).and_then(Option::take)),
    );
}

/// Stable sort of `v` by an `f64` key, ascending (total order).
pub fn sort_by_key_f64<T>(v: &mut Vec<T>, key: impl FnMut(&T) -> f64) {
    let keys: Vec<f64> = v.iter().map(key).collect();
    permute(v, &argsort(&keys));
}

/// Stable sort of `v` by an `f64` key, largest first (total order).
pub fn sort_by_key_f64_descending<T>(v: &mut Vec<T>, key: impl FnMut(&T) -> f64) {
    let keys: Vec<f64> = v.iter().map(key).collect();
    permute(v, &argsort_descending(&keys));
}

/// Stable sort of `v` by a `usize` key (a line number, an index), ascending. The keys are
/// compared as `f64`, exact below 2⁵³.
pub fn sort_by_index<T>(v: &mut Vec<T>, mut key: impl FnMut(&T) -> usize) {
    sort_by_key_f64(v, |x| {
        let k = key(x);
        debug_assert!((k as u64) < 1 << 53, "a key of {k} is not exact as f64");
        k as f64
    });
}

/// The indices of each label, the labels in the order they first appear and each group's
/// indices in the order given (one pass: a scan's points on hundreds of lines).
pub fn groups_in_order<'a>(
    labelled: impl IntoIterator<Item = (usize, &'a str)>,
) -> Vec<(&'a str, Vec<usize>)> {
    let mut out: Vec<(&str, Vec<usize>)> = Vec::new();
    let mut at: std::collections::HashMap<&str, usize> = std::collections::HashMap::new();
    // the group of the label before: a scan's points come a line at a time, so most labels are
    // their predecessor's and are not hashed (a dense scan's 200,000 labels, grouped several
    // times an analysis)
    let mut last: Option<(&str, usize)> = None;
    for (i, label) in labelled {
        let k = match last {
            Some((l, k)) if l == label => k,
            _ => *at.entry(label).or_insert_with(|| {
                out.push((label, Vec::new()));
                out.len() - 1
            }),
        };
        last = Some((label, k));
        out[k].1.push(i);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs of one label (a scan's lines) and labels coming back after others group as the
    /// labels do one by one.
    #[test]
    fn runs_of_a_label_group_as_single_labels() {
        let labels = ["x", "x", "y", "y", "y", "x", "z", "z", "y", "x"];
        let got = groups_in_order(labels.iter().copied().enumerate());
        assert_eq!(
            got,
            vec![
                ("x", vec![0, 1, 5, 9]),
                ("y", vec![2, 3, 4, 8]),
                ("z", vec![6, 7])
            ]
        );
    }

    #[test]
    fn groups_keep_the_first_appearance_order() {
        let labels = ["b", "a", "b", "c", "a"];
        let got = groups_in_order(labels.iter().copied().enumerate());
        assert_eq!(
            got,
            vec![("b", vec![0, 2]), ("a", vec![1, 4]), ("c", vec![3])]
        );
    }

    #[test]
    fn sorts_like_the_standard_stable_sort() {
        let keys = [
            3.0,
            -0.0,
            0.0,
            f64::NAN,
            -2.5,
            3.0,
            f64::INFINITY,
            -0.0,
            1e-300,
            f64::NEG_INFINITY,
        ];
        let mut want: Vec<usize> = (0..keys.len()).collect();
        want.sort_by(|&a, &b| keys[a].total_cmp(&keys[b]));
        assert_eq!(argsort(&keys), want);
        want.sort_by(|&a, &b| keys[b].total_cmp(&keys[a]));
        assert_eq!(argsort_descending(&keys), want);

        let mut x = keys.to_vec();
        sort_f64(&mut x);
        let mut y = keys.to_vec();
        y.sort_by(f64::total_cmp);
        assert_eq!(
            x.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            y.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        sort_f64_descending(&mut x);
        y.sort_by(|a, b| b.total_cmp(a));
        assert_eq!(
            x.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            y.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
    }

    #[test]
    fn keeps_equal_keys_in_order() {
        let mut v: Vec<(usize, &str)> = vec![(2, "a"), (0, "b"), (2, "c"), (1, "d"), (0, "e")];
        sort_by_index(&mut v, |x| x.0);
        assert_eq!(v, vec![(0, "b"), (0, "e"), (1, "d"), (2, "a"), (2, "c")]);
        let mut w = vec![(1.0, 'x'), (2.0, 'y'), (1.0, 'z')];
        sort_by_key_f64_descending(&mut w, |x| x.0);
        assert_eq!(w, vec![(2.0, 'y'), (1.0, 'x'), (1.0, 'z')]);
    }
}
