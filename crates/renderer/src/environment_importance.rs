//! The environment as a distribution of directions, for the path tracer's next-event
//! estimation to the environment (path_trace.glsl, `path_environment_sample`): the
//! sphere cut into [`COLUMNS`] × [`ROWS`] cells of equal solid angle — uniform in the
//! azimuth φ about +y and in y = cos θ (Lambert's cylindrical equal-area map) — each
//! drawn with probability proportional to the mean luminance of the environment's
//! radiance at 2 × 2 points of it, and a direction uniform within the cell: the density
//! per steradian is the cell's probability × `COLUMNS` · `ROWS` / 4π.
//!
//! The table (f32): its total luminance weight (0: nothing to sample, next-event
//! estimation to the environment is skipped), the marginal cumulative distribution over
//! the rows (`ROWS` + 1 values from 0 to 1), then each row's cumulative distribution over
//! its columns (`COLUMNS` + 1 values each). Built on the CPU from
//! `Environment::radiance` at bake (2 × 2 × 8,192 evaluations); a frame that does not path
//! trace never reads it.

use combustion_scene::Environment;

/// Cells around the azimuth.
pub const COLUMNS: usize = 128;

/// Cells from y = −1 to y = 1.
pub const ROWS: usize = 64;

/// The direction at the cell coordinates (`column`, `row`) (fractional: a cell spans one
/// unit of each): φ = 2π column / `COLUMNS`, y = −1 + 2 row / `ROWS`.
fn direction(column: f64, row: f64) -> [f64; 3] {
    let y = (-1.0 + 2.0 * row / ROWS as f64).clamp(-1.0, 1.0);
    let phi = std::f64::consts::TAU * column / COLUMNS as f64;
    let r = (1.0 - y * y).max(0.0).sqrt();
    [r * phi.cos(), y, r * phi.sin()]
}

/// A cumulative distribution of `weights` (n + 1 values from 0 to exactly 1); uniform
/// where they sum to 0.
fn cumulative(weights: &[f64]) -> Vec<f32> {
    let total: f64 = weights.iter().sum();
    let n = weights.len();
    let mut values = Vec::with_capacity(n + 1);
    let mut sum = 0.0;
    values.push(0.0);
    for (k, w) in weights.iter().enumerate() {
        sum += w;
        values.push(if total > 0.0 {
            (sum / total) as f32
        } else {
            (k + 1) as f32 / n as f32
        });
    }
    values[n] = 1.0;
    values
}

/// The table of `environment` (see the module docs).
pub fn importance_table(environment: &Environment) -> Vec<f32> {
    let mut cells = vec![0.0; COLUMNS * ROWS];
    for row in 0..ROWS {
        for column in 0..COLUMNS {
            let mut sum = 0.0;
            for (a, b) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)] {
                let [r, g, b] = environment.radiance(direction(column as f64 + a, row as f64 + b));
                let luminance = 0.2126 * r + 0.7152 * g + 0.0722 * b;
                if luminance.is_finite() && luminance > 0.0 {
                    sum += luminance;
                }
            }
            cells[row * COLUMNS + column] = sum / 4.0;
        }
    }
    let row_sums: Vec<f64> = cells
        .chunks_exact(COLUMNS)
        .map(|r| r.iter().sum())
        .collect();
    let total: f64 = row_sums.iter().sum();
    let mut table = Vec::with_capacity(1 + (ROWS + 1) + ROWS * (COLUMNS + 1));
    table.push(if total.is_finite() { total as f32 } else { 0.0 });
    table.extend(cumulative(&row_sums));
    for row in cells.chunks_exact(COLUMNS) {
        table.extend(cumulative(row));
    }
    table
}

/// path_trace.glsl's constants of the table's shape.
pub(crate) fn constants_glsl() -> String {
    format!("#define ENVIRONMENT_COLUMNS {COLUMNS}u\n#define ENVIRONMENT_ROWS {ROWS}u\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cell's probability from the table, as path_trace.glsl reads it.
    fn probability(table: &[f32], column: usize, row: usize) -> f64 {
        let marginal = &table[1..ROWS + 2];
        let start = 1 + ROWS + 1 + row * (COLUMNS + 1);
        let conditional = &table[start..start + COLUMNS + 1];
        f64::from(marginal[row + 1] - marginal[row])
            * f64::from(conditional[column + 1] - conditional[column])
    }

    #[test]
    fn a_uniform_environment_is_uniform_over_the_sphere() {
        let table = importance_table(&Environment::Uniform([0.3, 0.5, 0.7]));
        assert_eq!(table.len(), 1 + ROWS + 1 + ROWS * (COLUMNS + 1));
        let uniform = 1.0 / (COLUMNS * ROWS) as f64;
        for (column, row) in [(0, 0), (5, 31), (127, 63), (64, 20)] {
            assert!((probability(&table, column, row) - uniform).abs() < 1e-6 * uniform);
        }
    }

    #[test]
    fn the_brighter_half_is_drawn_in_proportion() {
        // The studio: brighter above than below; the probabilities sum to 1 and follow
        // the luminance.
        let table = importance_table(&Environment::Studio);
        let total: f64 = (0..ROWS)
            .flat_map(|row| (0..COLUMNS).map(move |column| (column, row)))
            .map(|(column, row)| probability(&table, column, row))
            .sum();
        assert!((total - 1.0).abs() < 1e-5, "{total}");
        let luminance = |d: [f64; 3]| {
            let [r, g, b] = Environment::Studio.radiance(d);
            0.2126 * r + 0.7152 * g + 0.0722 * b
        };
        let (up, down) = (
            probability(&table, 10, ROWS - 1),
            probability(&table, 10, 0),
        );
        let expected =
            luminance(direction(10.5, ROWS as f64 - 0.5)) / luminance(direction(10.5, 0.5));
        assert!(
            (up / down / expected - 1.0).abs() < 0.2,
            "{up} / {down} against {expected}"
        );
    }

    #[test]
    fn a_black_environment_has_nothing_to_sample() {
        let table = importance_table(&Environment::Uniform([0.0; 3]));
        assert_eq!(table[0], 0.0);
    }
}
