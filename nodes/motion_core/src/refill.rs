//! Refilling a snapshot in place ([`crate::Engine::snapshot_into`]): a lockstep state stream
//! takes a snapshot every cycle, so names and lists are written into the buffers of an older
//! snapshot instead of being allocated and dropped each time. Each function takes the old
//! value and returns the new one, so that snapshots are still built as struct literals (the
//! compiler checks that every field is written; nothing stale survives from the old one).

/// `s`, in `old`'s buffer.
pub fn reuse_str(mut old: String, s: &str) -> String {
    old.clear();
    old.push_str(s);
    old
}

/// `s`, in the buffer of `old`'s string when it has one.
pub fn reuse_opt_str(old: Option<String>, s: Option<&str>) -> Option<String> {
    match (old, s) {
        (Some(o), Some(s)) => Some(reuse_str(o, s)),
        (_, s) => s.map(str::to_owned),
    }
}

/// The names, in `old`'s vector and strings.
pub fn reuse_strs<'a>(
    mut old: Vec<String>,
    names: impl IntoIterator<Item = &'a str>,
) -> Vec<String> {
    let mut n = 0;
    for s in names {
        match old.get_mut(n) {
            Some(o) => *o = reuse_str(std::mem::take(o), s),
            None => old.push(s.to_owned()),
        }
        n += 1;
    }
    old.truncate(n);
    old
}

/// `n` items in `old`'s vector, item `i` made by `make(i, item)` from the item that was there (a
/// default one for new places): items keep their buffers from one snapshot to the next.
pub fn refill_vec<T: Default>(
    mut old: Vec<T>,
    n: usize,
    mut make: impl FnMut(usize, T) -> T,
) -> Vec<T> {
    old.truncate(n);
    old.resize_with(n, T::default);
    for (i, item) in old.iter_mut().enumerate() {
        *item = make(i, std::mem::take(item));
    }
    old
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_take_the_new_values_in_the_old_buffers() {
        let old = String::with_capacity(32);
        let p = old.as_ptr();
        let s = reuse_str(old, "m1");
        assert_eq!((s.as_str(), s.as_ptr()), ("m1", p));

        let o = reuse_opt_str(Some(String::from("track_a")), Some("b"));
        assert_eq!(o.as_deref(), Some("b"));
        let o = reuse_opt_str(o, None);
        assert_eq!(o, None);
        assert_eq!(reuse_opt_str(o, Some("c")).as_deref(), Some("c"));

        let v: Vec<String> = vec!["x".into(), "y".into(), "z".into()];
        let first = v[0].as_ptr();
        let v = reuse_strs(v, ["a", "b"]);
        assert_eq!(v, ["a", "b"]);
        assert_eq!(v[0].as_ptr(), first);
        let v = reuse_strs(v, ["a", "b", "c", "d"]);
        assert_eq!(v, ["a", "b", "c", "d"]);
        assert!(reuse_strs(v, []).is_empty());
    }

    #[test]
    fn a_refilled_vec_has_the_new_length_and_items() {
        let v = vec![(1, String::from("old")); 3];
        let v = refill_vec(v, 5, |i, old| (i, reuse_str(old.1, "new")));
        assert_eq!(v.len(), 5);
        assert!(v.iter().enumerate().all(|(i, x)| x.0 == i && x.1 == "new"));
        let v = refill_vec(v, 2, |i, old| (10 + i, old.1));
        assert_eq!(v.iter().map(|x| x.0).collect::<Vec<_>>(), [10, 11]);
    }
}
