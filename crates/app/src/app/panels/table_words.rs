//! The alias table in words and rows, shared by the table panel, its diagram and the
//! Sampling panel: the sentences that explain a column and a single draw in the seed
//! example's words, and the height of a table row.

use crate::app::state::AppState;
use crate::app::state::sampling::OneDraw;
use crate::numbers;

/// Rows of the table shown without scrolling when the table is small.
pub const ROW_HEIGHT: f32 = 18.0;

/// The sentence that explains column `i`, in the worked example's words: "column 1 keeps
/// light 1 with probability 6/27, else light 3".
pub fn column_sentence(state: &AppState, i: usize) -> String {
    let built = &state.built;
    let t = built.table.threshold(i);
    let a = built.table.alias(i) as usize;
    let p = numbers::show(t, built.denominator);
    if t >= 1.0 || a == i {
        format!("column {} always keeps light {}", i + 1, i + 1)
    } else if t <= 0.0 {
        format!(
            "column {} always gives light {} (light {} has power 0)",
            i + 1,
            a + 1,
            i + 1
        )
    } else {
        format!(
            "column {} keeps light {} with probability {p}, else light {}",
            i + 1,
            i + 1,
            a + 1
        )
    }
}

/// The sentence describing a single draw for the Sampling panel.
pub fn draw_sentence(state: &AppState, draw: &OneDraw) -> String {
    let den = state.built.denominator;
    let n = state.built.len();
    let t = numbers::show(draw.threshold, den);
    let verdict = if draw.kept {
        format!("U2 = {:.4} < {t} → keep light {}", draw.u2, draw.column + 1)
    } else {
        format!("U2 = {:.4} ≥ {t} → alias light {}", draw.u2, draw.light + 1)
    };
    format!(
        "U1 = {:.4} → column floor(U1·{n}) + 1 = {};  {verdict}",
        draw.u1,
        draw.column + 1
    )
}
