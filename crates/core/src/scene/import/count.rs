//! The light count a file may bring, checked before its lights are read one by one.

use crate::scene::{MAX_LIGHTS, SceneError};

/// Refuses more lights than a scene may hold, before they are read one by one.
pub(super) fn check_count(count: usize, what: &str) -> Result<(), SceneError> {
    if count > MAX_LIGHTS {
        return Err(SceneError::out_of_range(
            format!("{what} (count)"),
            count,
            1,
            MAX_LIGHTS,
        ));
    }
    Ok(())
}
