// The panel's 3-D view (three.js from Debian's libjs-three): the base and
// its joints, the legs coloured by the stroke they use, the platform at the
// measured pose (EDSP_PLATFORM_STATE.pose) and a ghost at the commanded one
// (target_pose), point A, the pivot, the base frame and the work frame of
// the last move (EDSP_MOTION_STATUS: its name and pose). The geometry is
// what the kinematics node runs with (EDSP_CONFIG), so the view is drawn
// from the model in use, not from a file the panel read. edsp's frames are
// z up; R_BM = Rz(yaw)·Ry(pitch)·Rx(roll), three.js's Euler order "ZYX".
"use strict";

const view3d = (() => {
  const JOINT_RADIUS_M = 0.03;
  const LEG_RADIUS_M = 0.025;
  // A leg's colour: red at either end of its stroke, green from this share
  // of the stroke away from both ends.
  const GREEN_FROM_SHARE = 0.25;

  const state = { ready: false, config: null, pose: null, target: null, pivot: [0, 0, 0], dirty: false,
                  frame: { name: "base", pose: [0, 0, 0, 0, 0, 0] } };
  let scene, camera, renderer, controls, platform, ghost, pivot, workFrame, legs = [], baseJoints = [];

  function vec(xyz) { return new THREE.Vector3(xyz[0], xyz[1], xyz[2]); }

  function finitePose(p) { return Array.isArray(p) && p.length === 6 && p.every((v) => typeof v === "number"); }

  function place(object, pose) {
    object.position.set(pose[0], pose[1], pose[2]);
    object.rotation.set(pose[3], pose[4], pose[5], "ZYX");
    object.updateMatrixWorld(true);
  }

  // The platform's outline through its joints, as a flat plate.
  function plate(joints, material) {
    const shape = new THREE.Shape(joints.map((p) => new THREE.Vector2(p[0], p[1])));
    const mesh = new THREE.Mesh(new THREE.ShapeGeometry(shape), material);
    mesh.position.z = joints[0][2];
    return mesh;
  }

  function sphere(radius, color) {
    return new THREE.Mesh(new THREE.SphereGeometry(radius, 16, 12), new THREE.MeshLambertMaterial({ color }));
  }

  function platformGroup(config, opacity) {
    const group = new THREE.Group();
    const material = new THREE.MeshLambertMaterial({
      color: 0x4a78c2, side: THREE.DoubleSide, transparent: opacity < 1, opacity, depthWrite: opacity >= 1 });
    group.add(plate(config.platform_joints_m, material));
    group.joints = config.platform_joints_m.map((p) => {
      const joint = sphere(JOINT_RADIUS_M, 0x20355a);
      joint.position.copy(vec(p));
      joint.material.transparent = opacity < 1;
      joint.material.opacity = opacity;
      group.add(joint);
      return joint;
    });
    return group;
  }

  function build(config, canvas) {
    scene = new THREE.Scene();
    scene.background = new THREE.Color(0xf4f5f7);
    scene.add(new THREE.AmbientLight(0xffffff, 0.6));
    const sun = new THREE.DirectionalLight(0xffffff, 0.6);
    sun.position.set(3, -4, 6);
    scene.add(sun);
    scene.add(new THREE.AxesHelper(0.5));  // {B}: x red, y green, z blue
    workFrame = new THREE.AxesHelper(0.3);  // the last move's work frame, where it is not {B}
    scene.add(workFrame);
    const base = plate(config.base_joints_m, new THREE.MeshLambertMaterial({ color: 0x8a8f98, side: THREE.DoubleSide }));
    scene.add(base);
    baseJoints = config.base_joints_m.map((p) => {
      const joint = sphere(JOINT_RADIUS_M, 0x333840);
      joint.position.copy(vec(p));
      scene.add(joint);
      return joint;
    });
    platform = platformGroup(config, 1.0);
    ghost = platformGroup(config, 0.25);
    const pointA = sphere(0.02, 0xd08020);
    pointA.position.copy(vec(config.observation_point_m));
    platform.add(pointA);
    pivot = sphere(0.02, 0x9040c0);
    platform.add(pivot);
    scene.add(platform, ghost);
    legs = config.base_joints_m.map(() => {
      const leg = new THREE.Mesh(new THREE.CylinderGeometry(LEG_RADIUS_M, LEG_RADIUS_M, 1, 12),
                                 new THREE.MeshLambertMaterial({ color: 0x40a040 }));
      scene.add(leg);
      return leg;
    });

    // preserveDrawingBuffer: the picture stays readable after it is shown (the
    // browser tests read its pixels); at 30 frames a second it costs nothing seen.
    renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    camera = new THREE.PerspectiveCamera(40, 1, 0.05, 50);
    camera.up.set(0, 0, 1);
    camera.position.set(4.5, -5.0, 3.5);
    controls = new THREE.OrbitControls(camera, canvas);
    controls.target.set(0, 0, config.home_height_m / 2);
    controls.addEventListener("change", () => { state.dirty = true; });
    controls.update();
    const home = [0, 0, config.home_height_m, 0, 0, 0];
    place(platform, home);
    place(ghost, home);
  }

  // Leg i from its base joint to its platform joint, as drawn.
  function legEnds(i) {
    return [baseJoints[i].getWorldPosition(new THREE.Vector3()),
            platform.joints[i].getWorldPosition(new THREE.Vector3())];
  }

  function strokeColour(length) {
    const span = state.config.leg_max_m - state.config.leg_min_m;
    const share = (length - state.config.leg_min_m) / span;
    const margin = Math.max(0, Math.min(share, 1 - share));  // 0 at either end
    return new THREE.Color().setHSL((Math.min(margin / GREEN_FROM_SHARE, 1) * 120) / 360, 0.7, 0.45);
  }

  function updateLegs() {
    legs.forEach((leg, i) => {
      const [bottom, top] = legEnds(i);
      const axis = top.clone().sub(bottom);
      const length = axis.length();
      leg.position.copy(bottom).addScaledVector(axis, 0.5);
      leg.scale.set(1, length, 1);
      leg.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), axis.normalize());
      leg.material.color.copy(strokeColour(length));
    });
  }

  function resize() {
    const canvas = renderer.domElement;
    const width = canvas.clientWidth, height = canvas.clientHeight;
    if (canvas.width !== width || canvas.height !== height) {
      renderer.setSize(width, height, false);
      camera.aspect = width / Math.max(height, 1);
      camera.updateProjectionMatrix();
      state.dirty = true;
    }
  }

  function frame() {
    requestAnimationFrame(frame);
    if (!state.ready) return;
    resize();
    if (!state.dirty) return;
    state.dirty = false;
    if (state.pose) place(platform, state.pose);
    if (state.target) place(ghost, state.target);
    pivot.position.copy(vec(state.pivot));
    place(workFrame, state.frame.pose);
    workFrame.visible = state.frame.name !== "base";
    updateLegs();
    renderer.render(scene, camera);
  }

  return {
    // EDSP_CONFIG: the first one builds the scene; a later one with other
    // joints or point A (another model) rebuilds it; the strokes are read
    // from the latest whatever it changed.
    setConfig(config, canvas) {
      const drawn = (c) => JSON.stringify([c.base_joints_m, c.platform_joints_m, c.observation_point_m, c.home_height_m]);
      const same = state.config && drawn(state.config) === drawn(config);
      if (typeof THREE === "undefined") {
        document.getElementById("view-note").textContent = "no 3-D view: three.js did not load";
        return;
      }
      state.config = config;
      state.dirty = true;
      if (same) return;
      if (renderer) renderer.dispose();
      build(config, canvas);
      state.ready = true;
      state.dirty = true;
    },
    // EDSP_PLATFORM_STATE: measured and commanded pose (a pose with a
    // non-finite value, sent as null, leaves the last one drawn).
    setPlatformState(message) {
      if (finitePose(message.pose)) state.pose = message.pose;
      if (finitePose(message.target_pose)) state.target = message.target_pose;
      state.dirty = true;
    },
    setPivot(point) {
      if (Array.isArray(point) && point.every((v) => typeof v === "number")) state.pivot = point;
      state.dirty = true;
    },
    // EDSP_MOTION_STATUS: the last move's frame and its pose in {B}.
    setWorkFrame(name, pose) {
      if (typeof name === "string" && finitePose(pose)) state.frame = { name: name || "base", pose };
      state.dirty = true;
    },
    // The work frame as drawn: its name, whether it shows, its origin and x axis in {B}.
    workFrame() {
      if (!state.ready) return null;
      workFrame.updateMatrixWorld(true);
      const origin = workFrame.getWorldPosition(new THREE.Vector3());
      const x = new THREE.Vector3(1, 0, 0).applyQuaternion(workFrame.getWorldQuaternion(new THREE.Quaternion()));
      return { name: state.frame.name, visible: workFrame.visible, origin: origin.toArray(), x_axis: x.toArray() };
    },
    // The legs as drawn: length (m) and share of the stroke used, each
    // from the scene's own joint positions (what the browser tests check
    // against the legs' encoders).
    legs() {
      if (!state.ready || !state.pose) return null;
      place(platform, state.pose);
      return legs.map((_, i) => {
        const [bottom, top] = legEnds(i);
        const length = top.distanceTo(bottom);
        return { length_m: length,
                 stroke_share: (length - state.config.leg_min_m) / (state.config.leg_max_m - state.config.leg_min_m) };
      });
    },
    rendered() { return state.ready && renderer.info.render.frame > 0; },
    renders() { return renderer ? renderer.info.render.frame : 0; },  // drawn so far (the web benchmark's counter)
    start() { requestAnimationFrame(frame); },
  };
})();
