//! Superlevel sets of a scalar field with a given area.

/// The vertices of highest `field` until their `mass` reaches `target_area` (ties broken by
/// index): the superlevel set $\{f \ge t\}$ whose area is the first to reach `target_area`.
/// Used for area-matched starts (a plane side, an eigenfunction's level set) and regions
/// (the eigenvector energy's superlevel set with the partial's area).
pub fn area_matched_set(field: &[f64], mass: &[f64], target_area: f64) -> Vec<bool> {
    let mut order: Vec<usize> = (0..field.len()).collect();
    order.sort_by(|&a, &b| field[b].total_cmp(&field[a]).then(a.cmp(&b)));
    let mut mask = vec![false; field.len()];
    let mut acc = 0.0;
    for i in order {
        if acc >= target_area {
            break;
        }
        mask[i] = true;
        acc += mass[i];
    }
    mask
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reaches_the_target_area_with_the_highest_values() {
        let field = [0.1, 0.9, 0.5, 0.7];
        let mass = [1.0; 4];
        assert_eq!(area_matched_set(&field, &mass, 2.0), vec![false, true, false, true]);
        assert_eq!(area_matched_set(&field, &mass, 2.5), vec![false, true, true, true]);
        assert_eq!(area_matched_set(&field, &mass, 0.0), vec![false; 4]);
    }
}
