//! The self-driving-car system under test: roads, the SBST competition's validator, the simulated
//! car and the drivers that steer it.
//!
//! Data flows one way, and so do the modules' dependencies:
//! - [`road`]: road points (or curvature values) are interpolated into a centre line, which gives
//!   the road's edges and lanes;
//! - [`validator`]: the competition's rules on them;
//! - [`vision`]: the camera's view of a road and DAVE-2's network;
//! - [`sim`]: one drive, a car in a rapier3d world steered by a [`Driver`] and watched by the
//!   lane monitor, ending in a [`SimResult`];
//! - [`driver`]: the drivers under test, each with its tuning, and the competition's setup each
//!   is judged by;
//! - [`oob`]: the SBST competition's analysis of out-of-bound episodes (sides, sparseness);
//! - [`distinct`]: how many failing roads differ around where the car left its lane.
//!
//! ```
//! use road_sim::driver::{CompetitionSetup, DriverConfig, DriverKind};
//! use road_sim::{simulate, Outcome, Road};
//!
//! let road = Road::new(&[[100.0, 10.0], [100.0, 60.0], [100.0, 110.0]]).unwrap();
//! let kind = DriverKind::BeamNgAiProxy;
//! let driver = DriverConfig::default_for(kind);
//! let sim = CompetitionSetup::of(kind).sim_config();
//! let result = simulate(&road, driver.build().as_mut(), &sim, false, None);
//! assert_eq!(result.outcome, Outcome::Pass);
//! ```

pub mod distinct;
pub mod driver;
pub mod json_float;
pub mod oob;
pub mod road;
pub mod setting_checks;
pub mod sim;
pub mod validator;
pub mod vision;

pub use driver::{CompetitionSetup, DriverConfig, DriverKind};
pub use road::{CurvatureRoad, Point, Road, RoadFeatures, RoadPlacement};
pub use setting_checks::SettingsError;
pub use sim::{
    simulate, Driver, FitnessKind, LaneExit, LaneSide, Observation, Outcome, Sample, SimConfig,
    SimResult, StopReason,
};
pub use validator::{Reason, Validator, Verdict};
