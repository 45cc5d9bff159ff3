//! The car: a rapier3d rigid body on rapier's ray-cast vehicle controller (four wheels with
//! suspension, rear-wheel drive, brakes on all wheels, rate- and angle-limited front steering).
//!
//! # Frames
//! The road plane (x east, y north, metres, `f64`) maps to rapier's world (`f32`, y up) as
//! `X = x - origin_x`, `Y = height`, `Z = -(y - origin_y)`, with `origin` the car's start point
//! (so that `f32` keeps millimetres). A 2D heading `h` (counter-clockwise from east) is a rotation
//! by `h` about rapier's `+Y`. The chassis' local axes are `+X` forward, `+Y` up, `+Z` right.
//! Positive steering turns left.

use crate::road::Point;
use crate::setting_checks::{all_within, SettingsError};
use rapier3d::control::{DynamicRayCastVehicleController, WheelTuning};
use rapier3d::prelude::*;
use serde::{Deserialize, Serialize};

/// Physical parameters of the car (a mid-size sedan by default).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct VehicleParams {
    /// Body length, metres (the footprint the lane monitor measures).
    pub length_m: f64,
    /// Body width, metres.
    pub width_m: f64,
    /// Mass, kilograms.
    pub mass_kg: f64,
    /// Distance from the centre of mass to the front axle, metres.
    pub cg_to_front_axle_m: f64,
    /// Distance from the centre of mass to the rear axle, metres.
    pub cg_to_rear_axle_m: f64,
    /// Distance between the left and right wheels, metres.
    pub track_m: f64,
    /// Wheel radius, metres.
    pub wheel_radius_m: f64,
    /// Yaw moment of inertia, kg m².
    pub yaw_inertia_kg_m2: f64,
    /// Largest drive force of the engine (both rear wheels together), newtons.
    pub max_drive_force_n: f64,
    /// Engine power: the drive force is limited to `power / speed`, watts.
    pub max_power_w: f64,
    /// Largest brake force (all wheels together), newtons.
    pub max_brake_force_n: f64,
    /// Largest steering angle of the front wheels, radians.
    pub max_steering_rad: f64,
    /// Fastest change of the front wheels' steering angle, radians per second.
    pub max_steering_rate_rad_s: f64,
    /// Tyre friction coefficient (rapier's `friction_slip`).
    pub tyre_friction: f64,
    /// Multiplier of the tyres' lateral grip (rapier's `side_friction_stiffness`).
    pub side_friction_stiffness: f64,
    /// Suspension stiffness per unit of chassis mass (rapier's convention), 1/s².
    pub suspension_stiffness: f64,
    /// Linear damping of the chassis (air drag and rolling resistance), 1/s.
    pub linear_damping: f64,
}

impl Default for VehicleParams {
    fn default() -> Self {
        Self {
            length_m: 4.6,
            width_m: 1.9,
            mass_kg: 1500.0,
            cg_to_front_axle_m: 1.3,
            cg_to_rear_axle_m: 1.5,
            track_m: 1.6,
            wheel_radius_m: 0.32,
            yaw_inertia_kg_m2: 2700.0,
            max_drive_force_n: 5000.0,
            max_power_w: 110_000.0,
            max_brake_force_n: 13_000.0,
            max_steering_rad: 0.6,
            max_steering_rate_rad_s: 0.8,
            tyre_friction: 1.0,
            side_friction_stiffness: 1.0,
            suspension_stiffness: 25.0,
            linear_damping: 0.01,
        }
    }
}

impl VehicleParams {
    /// Names the first parameter no car can have. Each has a range around a road car's (a
    /// bicycle's mass to a lorry's, say) that keeps rapier's solver and the lane monitor in the
    /// numbers they work with; the default car lies well inside every one.
    pub fn validate(&self) -> Result<(), SettingsError> {
        all_within(
            "vehicle.",
            &[
                ("length_m", self.length_m, 0.5, 30.0),
                ("width_m", self.width_m, 0.5, 5.0),
                ("mass_kg", self.mass_kg, 10.0, 100_000.0),
                ("cg_to_front_axle_m", self.cg_to_front_axle_m, 0.1, 15.0),
                ("cg_to_rear_axle_m", self.cg_to_rear_axle_m, 0.1, 15.0),
                ("track_m", self.track_m, 0.2, 5.0),
                ("wheel_radius_m", self.wheel_radius_m, 0.05, 2.0),
                ("yaw_inertia_kg_m2", self.yaw_inertia_kg_m2, 1.0, 1e7),
                ("max_drive_force_n", self.max_drive_force_n, 1.0, 1e6),
                ("max_power_w", self.max_power_w, 1.0, 1e8),
                ("max_brake_force_n", self.max_brake_force_n, 1.0, 1e6),
                ("max_steering_rad", self.max_steering_rad, 0.01, 1.5),
                (
                    "max_steering_rate_rad_s",
                    self.max_steering_rate_rad_s,
                    0.01,
                    100.0,
                ),
                ("tyre_friction", self.tyre_friction, 0.01, 10.0),
                (
                    "side_friction_stiffness",
                    self.side_friction_stiffness,
                    0.01,
                    100.0,
                ),
                (
                    "suspension_stiffness",
                    self.suspension_stiffness,
                    1.0,
                    1000.0,
                ),
                ("linear_damping", self.linear_damping, 0.0, 10.0),
            ],
        )
    }

    /// Distance between the axles, metres.
    pub fn wheelbase_m(&self) -> f64 {
        self.cg_to_front_axle_m + self.cg_to_rear_axle_m
    }
}

/// What a driver asks of the car.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Command {
    /// Steering angle of the front wheels, radians, positive left (clamped to the car's limit
    /// and reached at the car's steering rate).
    pub steering_rad: f64,
    /// Throttle in `[0, 1]`.
    pub throttle: f64,
    /// Brake in `[0, 1]` (overrides the throttle when positive).
    pub brake: f64,
}

/// The car's state in the road plane.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct CarState {
    /// Position of the centre of the body, `[x, y]` metres.
    pub position: Point,
    /// Heading, radians counter-clockwise from east.
    pub heading_rad: f64,
    /// Speed over ground, metres per second.
    pub speed_mps: f64,
    /// Forward speed (negative when reversing), metres per second.
    pub forward_speed_mps: f64,
    /// Yaw rate, radians per second, positive counter-clockwise.
    pub yaw_rate_rad_s: f64,
    /// Current steering angle of the front wheels, radians, positive left.
    pub steering_rad: f64,
}

/// Index of the wheels in the controller: front left, front right, rear left, rear right.
const FRONT: [usize; 2] = [0, 1];
const REAR: [usize; 2] = [2, 3];
/// Height of the wheels' suspension mounts under the centre of mass, metres.
const MOUNT_BELOW_CG_M: f32 = 0.25;
/// Rest length of the suspension, metres.
const SUSPENSION_REST_M: f32 = 0.3;

/// A car in its own rapier world (flat ground).
pub struct Vehicle {
    params: VehicleParams,
    world: PhysicsWorld,
    controller: DynamicRayCastVehicleController,
    chassis: RigidBodyHandle,
    origin: Point,
    dt: f64,
    steering_rad: f64,
}

impl Vehicle {
    /// A car at rest at `position` heading `heading_rad`, stepped at `physics_hz`.
    pub fn new(params: VehicleParams, position: Point, heading_rad: f64, physics_hz: f64) -> Self {
        let mut world = PhysicsWorld::default();
        let dt = 1.0 / physics_hz;
        world.integration_parameters.dt = dt as f32;
        // The ground: a large slab whose top is Y = 0.
        world.insert(
            RigidBodyBuilder::fixed().translation(Vector::new(0.0, -1.0, 0.0)),
            ColliderBuilder::cuboid(2000.0, 1.0, 2000.0).friction(1.0),
        );
        let p = params;
        let (m, yaw_i) = (p.mass_kg as f32, p.yaw_inertia_kg_m2 as f32);
        // Roll and pitch inertia of a sedan relative to its yaw inertia.
        let inertia = Vector::new(0.2 * yaw_i, yaw_i, 0.95 * yaw_i);
        let start_height = MOUNT_BELOW_CG_M + SUSPENSION_REST_M + p.wheel_radius_m as f32 - 0.08;
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, start_height, 0.0))
            .rotation(Vector::new(0.0, heading_rad as f32, 0.0))
            .additional_mass_properties(MassProperties::new(Vector::ZERO, m, inertia))
            .linear_damping(p.linear_damping as f32)
            .can_sleep(false);
        let chassis = world.insert_body(body);
        let mut controller = DynamicRayCastVehicleController::new(chassis);
        controller.index_up_axis = 1;
        controller.index_forward_axis = 0;
        let tuning = WheelTuning {
            suspension_stiffness: p.suspension_stiffness as f32,
            suspension_compression: 1.6,
            suspension_damping: 2.2,
            max_suspension_travel: 0.2,
            side_friction_stiffness: p.side_friction_stiffness as f32,
            friction_slip: p.tyre_friction as f32,
            max_suspension_force: 4.0 * m * 9.81,
        };
        let (front, rear, half_track) = (
            p.cg_to_front_axle_m as f32,
            -(p.cg_to_rear_axle_m as f32),
            (p.track_m / 2.0) as f32,
        );
        for (x, z) in [
            (front, -half_track),
            (front, half_track),
            (rear, -half_track),
            (rear, half_track),
        ] {
            controller.add_wheel(
                Vector::new(x, -MOUNT_BELOW_CG_M, z),
                Vector::NEG_Y,
                Vector::Z,
                SUSPENSION_REST_M,
                p.wheel_radius_m as f32,
                &tuning,
            );
        }
        // Fill the broad phase so that the wheels' first ray casts see the ground.
        world.detect_collisions(&(), &());
        Self {
            params,
            world,
            controller,
            chassis,
            origin: position,
            dt,
            steering_rad: 0.0,
        }
    }

    /// The car's parameters.
    pub fn params(&self) -> &VehicleParams {
        &self.params
    }

    /// Applies `command` and advances the world by one physics step.
    pub fn step(&mut self, command: &Command) {
        let p = &self.params;
        let target = command
            .steering_rad
            .clamp(-p.max_steering_rad, p.max_steering_rad);
        let max_change = p.max_steering_rate_rad_s * self.dt;
        self.steering_rad += (target - self.steering_rad).clamp(-max_change, max_change);
        let speed = f64::from(self.controller.current_vehicle_speed).abs();
        let brake = command.brake.clamp(0.0, 1.0);
        let throttle = if brake > 0.0 {
            0.0
        } else {
            command.throttle.clamp(0.0, 1.0)
        };
        let drive =
            (p.max_drive_force_n.min(p.max_power_w / speed.max(1.0)) * throttle / 2.0) as f32;
        let brake_impulse = (p.max_brake_force_n * brake / 4.0 * self.dt) as f32;
        let steering = self.steering_rad as f32;
        let wheels = self.controller.wheels_mut();
        for i in FRONT {
            wheels[i].steering = steering;
            wheels[i].engine_force = 0.0;
        }
        for i in REAR {
            wheels[i].engine_force = drive;
        }
        for wheel in wheels.iter_mut() {
            wheel.brake = brake_impulse;
        }
        let filter = QueryFilter::default().exclude_rigid_body(self.chassis);
        let w = &mut self.world;
        let queries = w.broad_phase.as_query_pipeline_mut(
            w.narrow_phase.query_dispatcher(),
            &mut w.bodies,
            &mut w.colliders,
            filter,
        );
        self.controller.update_vehicle(self.dt as f32, queries);
        self.world.step();
    }

    /// The car's state in the road plane.
    pub fn state(&self) -> CarState {
        let body = &self.world.bodies[self.chassis];
        let pose = body.position();
        let forward = pose.rotation * Vector::X;
        let t = pose.translation;
        let v = body.linvel();
        let heading = f64::from(-forward.z).atan2(f64::from(forward.x));
        let (vx, vy) = (f64::from(v.x), -f64::from(v.z));
        CarState {
            position: [
                self.origin[0] + f64::from(t.x),
                self.origin[1] - f64::from(t.z),
            ],
            heading_rad: heading,
            speed_mps: vx.hypot(vy),
            forward_speed_mps: vx * heading.cos() + vy * heading.sin(),
            yaw_rate_rad_s: f64::from(body.angvel().y),
            steering_rad: self.steering_rad,
        }
    }

    /// Height of the centre of mass above the ground, metres.
    pub fn height_m(&self) -> f64 {
        f64::from(self.world.bodies[self.chassis].position().translation.y)
    }

    /// Whether the chassis' pose and velocities are all finite (and rapier did not quarantine
    /// the chassis for going non-finite).
    pub fn is_finite(&self) -> bool {
        let body = &self.world.bodies[self.chassis];
        let pose = body.position();
        self.world.quarantine().bodies().is_empty()
            && body.is_enabled()
            && pose.translation.is_finite()
            && pose.rotation.is_finite()
            && body.linvel().is_finite()
            && body.angvel().is_finite()
    }
}

/// The four corners of a `length_m` x `width_m` rectangle centred at `center` with heading
/// `heading_rad`: front left, front right, rear right, rear left.
pub fn footprint(center: Point, heading_rad: f64, length_m: f64, width_m: f64) -> [Point; 4] {
    let (s, c) = heading_rad.sin_cos();
    let (hl, hw) = (length_m / 2.0, width_m / 2.0);
    let at = |f: f64, l: f64| [center[0] + f * c - l * s, center[1] + f * s + l * c];
    [at(hl, hw), at(hl, -hw), at(-hl, -hw), at(-hl, hw)]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drive(v: &mut Vehicle, command: Command, seconds: f64) {
        for _ in 0..(seconds * 60.0).round() as usize {
            v.step(&command);
        }
    }

    #[test]
    fn settles_on_its_wheels_and_stays_put() {
        let mut v = Vehicle::new(VehicleParams::default(), [100.0, 10.0], 1.0, 60.0);
        drive(&mut v, Command::default(), 3.0);
        let s = v.state();
        assert!(v.is_finite());
        assert!((v.height_m() - 0.77).abs() < 0.1, "height {}", v.height_m());
        assert!(s.speed_mps < 0.05, "speed {}", s.speed_mps);
        assert!((s.position[0] - 100.0).abs() < 0.05 && (s.position[1] - 10.0).abs() < 0.05);
        assert!((s.heading_rad - 1.0).abs() < 1e-3);
    }

    #[test]
    fn throttle_moves_it_forward_along_its_heading_and_brakes_stop_it() {
        let heading = 2.0_f64;
        let mut v = Vehicle::new(VehicleParams::default(), [0.0, 0.0], heading, 60.0);
        drive(
            &mut v,
            Command {
                throttle: 1.0,
                ..Command::default()
            },
            4.0,
        );
        let s = v.state();
        assert!(
            s.forward_speed_mps > 8.0 && s.forward_speed_mps < 16.0,
            "speed {}",
            s.speed_mps
        );
        let along = s.position[0] * heading.cos() + s.position[1] * heading.sin();
        let across = -s.position[0] * heading.sin() + s.position[1] * heading.cos();
        assert!(
            along > 15.0 && across.abs() < 0.2,
            "along {along} across {across}"
        );
        drive(
            &mut v,
            Command {
                brake: 1.0,
                ..Command::default()
            },
            4.0,
        );
        assert!(v.state().speed_mps < 0.2);
    }

    #[test]
    fn positive_steering_turns_left() {
        let mut v = Vehicle::new(VehicleParams::default(), [0.0, 0.0], 0.0, 60.0);
        let command = Command {
            throttle: 0.3,
            steering_rad: 0.2,
            brake: 0.0,
        };
        drive(&mut v, command, 3.0);
        let s = v.state();
        assert!(s.heading_rad > 0.3 && s.position[1] > 1.0, "{s:?}");
        assert!((s.steering_rad - 0.2).abs() < 1e-9);
    }

    /// Lateral acceleration (g) of the car on a skidpad: front wheels held at 0.2 rad (a circle
    /// of about 14 m), throttle holding `speed_mps`, averaged over the last two of eight seconds.
    fn skidpad_lateral_g(speed_mps: f64) -> f64 {
        let mut v = Vehicle::new(VehicleParams::default(), [0.0, 0.0], 0.0, 60.0);
        let mut total = 0.0;
        for step in 0..480 {
            let s = v.state();
            let throttle = (0.5 * (speed_mps - s.forward_speed_mps)).clamp(0.0, 1.0);
            v.step(&Command {
                steering_rad: 0.2,
                throttle,
                brake: 0.0,
            });
            if step >= 360 {
                let s = v.state();
                total += s.speed_mps * s.yaw_rate_rad_s.abs() / 9.81;
            }
        }
        total / 120.0
    }

    /// The beamng-ai-proxy calibration rests on where the tyres give way on a steady arc: with
    /// `tyre_friction` 1.0 they hold a little under 1 g, and a circle asked to need more is
    /// driven wider at that limit.
    #[test]
    fn holds_a_steady_circle_up_to_about_one_g() {
        let gentle = skidpad_lateral_g(8.0);
        let wheelbase_m = VehicleParams::default().wheelbase_m();
        let kinematic = 8.0_f64.powi(2) * 0.2_f64.tan() / wheelbase_m / 9.81;
        assert!((gentle - kinematic).abs() < 0.1 * kinematic, "{gentle} g");
        let limit = skidpad_lateral_g(14.0);
        eprintln!(
            "skidpad: {gentle:.3} g at 8 m/s (kinematic {kinematic:.3}), {limit:.3} g at 14 m/s"
        );
        assert!(limit > 0.9 && limit < 1.0, "{limit} g at the limit");
    }

    #[test]
    fn footprint_corners() {
        let c = footprint([1.0, 2.0], std::f64::consts::FRAC_PI_2, 4.0, 2.0);
        let expected = [[0.0, 4.0], [2.0, 4.0], [2.0, 0.0], [0.0, 0.0]];
        for (a, b) in c.iter().zip(expected) {
            assert!(
                (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12,
                "{c:?}"
            );
        }
    }
}
