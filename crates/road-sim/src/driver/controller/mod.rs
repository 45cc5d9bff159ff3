//! `--oracle cmd:"COMMAND"`: a lane keeper in another process (a team's controller in Python, C++,
//! ...) drives wogan's car. At each control step the driver writes what a lane keeper sees (one
//! [`protocol`] line) and applies the steering, throttle and brake read back. Controllers are
//! started as drives need them, one per worker, and reused across drives; a controller that fails
//! a step (ends, answers late, writes garbage, a number out of range, a reply to another step or a
//! second reply) is killed and reaped, the drive ends as `ERROR` with the reason and the tail of
//! its stderr ([`Driver::failure`]), and the next drive starts a new one.

pub mod protocol;

use crate::road::{polyline, Point, Road};
use crate::setting_checks::{first_problem, SettingsError};
use crate::sim::{Command, Driver, Observation, VehicleParams};
use crate::vision::{Camera, CameraParams, Frame, RoadScene};
use child_process::{ChildProcess, Fault};
use protocol::{parse_reply, CameraFrame, Message, PROTOCOL, VERSION};
use serde::{Deserialize, Serialize};
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// A controller's settings (a config file's `driver` section); the command itself comes only from
/// the command line.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ControllerParams {
    /// Control steps per simulated second.
    pub control_hz: f64,
    /// Longest wait for one step's reply, seconds.
    pub step_timeout_s: f64,
    /// Longest wait for the first reply of a controller just started, seconds: its start-up
    /// (an interpreter, a model loaded) is not a step's work.
    pub start_timeout_s: f64,
    /// Whether each step carries the front camera's gray frame (66 x 200, DAVE-2's).
    pub camera: bool,
    /// Points of the lane centre ahead given per step.
    pub ahead_points: usize,
    /// Spacing of those points along the lane, metres.
    pub ahead_spacing_m: f64,
}

impl Default for ControllerParams {
    fn default() -> Self {
        Self {
            control_hz: 20.0,
            step_timeout_s: 1.0,
            start_timeout_s: 30.0,
            camera: false,
            ahead_points: 10,
            ahead_spacing_m: 3.0,
        }
    }
}

impl ControllerParams {
    /// Names the first setting a controller cannot be driven with.
    pub fn validate(&self) -> Result<(), SettingsError> {
        first_problem(&[
            (
                self.control_hz > 0.0 && self.control_hz <= 1000.0,
                "driver.control_hz",
                "in (0, 1000]",
            ),
            (
                self.step_timeout_s > 0.0 && self.step_timeout_s <= 3600.0,
                "driver.step_timeout_s",
                "in (0, 3600]",
            ),
            (
                self.start_timeout_s > 0.0 && self.start_timeout_s <= 3600.0,
                "driver.start_timeout_s",
                "in (0, 3600]",
            ),
            (
                (1..=100).contains(&self.ahead_points),
                "driver.ahead_points",
                "from 1 to 100",
            ),
            (
                self.ahead_spacing_m > 0.0 && self.ahead_spacing_m <= 50.0,
                "driver.ahead_spacing_m",
                "in (0, 50]",
            ),
        ])
    }
}

/// A controller to drive with: its command, settings, and the processes idle between drives.
#[derive(Debug, Clone)]
pub struct ControllerConfig {
    /// The command, as typed after `cmd:` on the command line.
    pub command: String,
    /// Its settings.
    pub params: ControllerParams,
    idle: Arc<Mutex<Vec<ChildProcess>>>,
}

impl ControllerConfig {
    /// A controller run as `command` (with `sh -c`).
    pub fn new(command: String, params: ControllerParams) -> Self {
        Self {
            command,
            params,
            idle: Arc::new(Mutex::new(Vec::new())),
        }
    }

    /// A driver for one drive.
    pub fn build(&self) -> ControllerDriver {
        ControllerDriver {
            config: self.clone(),
            process: None,
            step: 0,
            failure: None,
            lane: Vec::new(),
            max_steering_rad: 0.0,
            window: 0,
            camera: self.params.camera.then(|| {
                (
                    Camera::new(CameraParams::default()),
                    Frame::new(0, 0, 1),
                    None,
                )
            }),
        }
    }
}

/// The driver of one drive.
pub struct ControllerDriver {
    config: ControllerConfig,
    process: Option<ChildProcess>,
    /// The number of the last step sent in this drive.
    step: u64,
    failure: Option<String>,
    /// The right lane's centre.
    lane: Vec<Point>,
    max_steering_rad: f64,
    /// The lane segment the car was last projected on (searched around, not from the start).
    window: usize,
    camera: Option<(Camera, Frame, Option<RoadScene>)>,
}

/// Never set: a controller's wait ends by its deadline, or at once when the process is stopping
/// ([`child_process::stop_all`]).
static NEVER: AtomicBool = AtomicBool::new(false);

impl ControllerDriver {
    fn fail(&mut self, what: String) {
        let stderr = self
            .process
            .take()
            .map(|p| p.stderr_tail())
            .unwrap_or_default();
        let mut reason = format!("the controller: {what}");
        if !stderr.is_empty() {
            reason.push_str(&format!("; its stderr ended with:\n{stderr}"));
        }
        self.failure.get_or_insert(reason);
    }

    /// What the step message says of the car's place in its lane.
    fn step_message(&mut self, o: &Observation<'_>) -> Message<'static> {
        let car = &o.car;
        let n = self.lane.len();
        let window = (
            self.window.saturating_sub(20),
            (self.window + 40).min(n - 1),
        );
        let mut p = polyline::project(car.position, &self.lane, Some(window));
        if p.distance_m > 10.0 {
            p = polyline::project(car.position, &self.lane, None);
        }
        self.window = p.segment;
        let (a, b) = (self.lane[p.segment], self.lane[(p.segment + 1).min(n - 1)]);
        let lane_heading = (b[1] - a[1]).atan2(b[0] - a[0]);
        let error = car.heading_rad - lane_heading;
        let heading_error_rad =
            (error + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        // Lane points ahead, every `spacing` metres, in the car's frame.
        let (cos, sin) = (car.heading_rad.cos(), car.heading_rad.sin());
        let params = self.config.params;
        let mut ahead = Vec::with_capacity(params.ahead_points);
        let mut walked = 0.0;
        let mut next = params.ahead_spacing_m;
        let mut previous = car.position;
        for &q in &self.lane[(p.segment + 1).min(n - 1)..] {
            walked += (q[0] - previous[0]).hypot(q[1] - previous[1]);
            previous = q;
            if walked >= next {
                let (dx, dy) = (q[0] - car.position[0], q[1] - car.position[1]);
                ahead.push([dx * cos + dy * sin, -dx * sin + dy * cos]);
                next += params.ahead_spacing_m;
                if ahead.len() == params.ahead_points {
                    break;
                }
            }
        }
        let camera = self.camera.as_mut().and_then(|(camera, frame, scene)| {
            let scene = scene.as_ref()?;
            camera.render_into(scene, car.position, car.heading_rad, frame);
            Some(CameraFrame {
                width: frame.width,
                height: frame.height,
                gray: frame.data.clone(),
            })
        });
        Message::Step {
            step: self.step,
            t: o.time_s,
            speed_mps: car.speed_mps,
            x: car.position[0],
            y: car.position[1],
            heading_rad: car.heading_rad,
            lateral_offset_m: p.lateral_m,
            heading_error_rad,
            ahead,
            camera,
        }
    }
}

impl Driver for ControllerDriver {
    fn name(&self) -> &'static str {
        "controller"
    }

    fn control_hz(&self) -> f64 {
        self.config.params.control_hz
    }

    fn reset(&mut self, road: &Road, vehicle: &VehicleParams, speed_limit_mps: f64) {
        self.lane = road.right_lane_centre();
        self.max_steering_rad = vehicle.max_steering_rad;
        self.window = 0;
        self.step = 0;
        if let Some((_, _, scene)) = &mut self.camera {
            *scene = Some(RoadScene::new(road));
        }
        let idle = self
            .config
            .idle
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .pop();
        let process = match idle {
            Some(process) => Ok(process),
            None => {
                let hello = Message::Hello {
                    protocol: PROTOCOL,
                    version: VERSION,
                    units: "metres, seconds, radians",
                    control_hz: self.config.params.control_hz,
                    camera: self.config.params.camera,
                };
                ChildProcess::start(&self.config.command, &hello, &Message::Bye)
            }
        };
        match process {
            Ok(process) => self.process = Some(process),
            Err(fault) => return self.fail(fault.to_string()),
        }
        let road_line = Message::Road {
            road_points: &road.road_points,
            lane_centre: &self.lane,
            speed_limit_mps,
            max_steering_rad: self.max_steering_rad,
        };
        let sent = self.process.as_mut().map(|p| p.send(&road_line));
        if let Some(Err(fault)) = sent {
            self.fail(fault.to_string());
        }
    }

    fn act(&mut self, observation: &Observation<'_>) -> Command {
        let failed = Command {
            steering_rad: f64::NAN,
            throttle: 0.0,
            brake: 1.0,
        };
        if self.failure.is_some() || self.process.is_none() {
            return failed;
        }
        self.step += 1;
        let step = self.step_message(observation);
        let params = &self.config.params;
        let asked = self.step;
        let answered = self.process.as_mut().map(|p| {
            // A process that has answered nothing yet is still starting (an interpreter, a model
            // loaded): its first reply is not held to a step's deadline.
            let timeout = Duration::from_secs_f64(if p.has_answered() {
                params.step_timeout_s
            } else {
                params.start_timeout_s.max(params.step_timeout_s)
            });
            p.answer(&step, asked, timeout, &NEVER, |line, answered| {
                parse_reply(line, asked, answered)
            })
        });
        let reply = match answered {
            Some(Ok(reply)) => reply.map_err(|e| e.to_string()),
            // The process is stopping (Ctrl-C): brake; the drive is cut short, not failed.
            Some(Err(Fault::Stopped)) => {
                return Command {
                    steering_rad: 0.0,
                    throttle: 0.0,
                    brake: 1.0,
                }
            }
            Some(Err(fault)) => Err(fault.to_string()),
            None => Err("not running".to_owned()),
        };
        match reply {
            Ok(reply) => Command {
                steering_rad: reply.steering * self.max_steering_rad,
                throttle: reply.throttle,
                brake: reply.brake,
            },
            Err(problem) => {
                self.fail(format!("at t = {:.2} s: {problem}", observation.time_s));
                failed
            }
        }
    }

    fn failure(&self) -> Option<String> {
        self.failure.clone()
    }
}

impl Drop for ControllerDriver {
    fn drop(&mut self) {
        // A controller that drove well ends its drive and waits for the next; one that failed
        // was dropped (killed and reaped) when it failed.
        if let Some(mut process) = self.process.take() {
            if process.send(&Message::End).is_ok() {
                self.config
                    .idle
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .push(process);
            }
        }
    }
}
