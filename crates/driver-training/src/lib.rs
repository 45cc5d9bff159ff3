//! How `dave2-proxy`'s weights are made: DAVE-2 as a burn model ([`dave2_model`]) and behaviour
//! cloning from the `beamng-ai-proxy` teacher ([`behaviour_cloning`]). The simulator only needs
//! the weights ([`road_sim::vision::Dave2Weights`]), so it does not depend on burn; this crate does.

pub mod behaviour_cloning;
pub mod dave2_model;

pub use behaviour_cloning::{
    random_valid_roads, train, CloningConfig, CloningProgress, CloningReport, Diverged,
    RandomRoads, BUILT_IN_STUDENT_TEACHER, MAX_DRAWS_PER_ROAD,
};
pub use dave2_model::{predict_burn, Dave2, Dave2Trainer};
