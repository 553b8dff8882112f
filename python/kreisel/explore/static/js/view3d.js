// The 3D view: the body as the server describes it (kreisel.explore._geometry.body_parts),
// posed at each sample of the run, on a floor, with the traces of the figure axis's tip and
// of the contact point. z is up, as in kreisel.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

function stripes(a, b, n) {
  const canvas = document.createElement('canvas');
  canvas.width = 256;
  canvas.height = 16;
  const g = canvas.getContext('2d');
  for (let k = 0; k < n; k++) {
    g.fillStyle = k % 2 ? b : a;
    g.fillRect((k * 256) / n, 0, 256 / n + 1, 16);
  }
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  return texture;
}

// the contact arrows' colours (the legend of the 3D view shows them)
export const ARROW_COLOURS = { point: 0x111111, normal: 0x1f5fa8, friction: 0xc0392b };

// three's spheres and lathes turn about y; kreisel's figure axis e3 is z
const Y_TO_Z = new THREE.Matrix4().makeRotationX(Math.PI / 2);

// The distance from the body's origin (G, or the pivot) to the farthest point of its parts (m).
export function bodyReach(parts) {
  let reach = 0;
  for (const p of parts) {
    if (p.kind === 'sphere') reach = Math.max(reach, Math.abs(p.z) + p.radius);
    else if (p.kind === 'lathe') for (const [r, z] of p.profile) reach = Math.max(reach, Math.hypot(r, z));
    else if (p.kind === 'ellipsoid') reach = Math.max(reach, Math.hypot(...p.center) + Math.max(...p.radii));
    else if (p.kind === 'rod') reach = Math.max(reach, Math.hypot(...p.start), Math.hypot(...p.end));
  }
  return reach;
}

// A body of spheroids and rings is drawn as its parts and, around them, the outline of their
// union (the necks between them): that outline runs on the parts' own surfaces, so it is drawn
// 1 % inside them, else the two coincident surfaces fight for each pixel (z-fighting).
const HULL_INSIDE = 0.99;

function mesh(part, materials, inside = 1) {
  let geometry;
  if (part.kind === 'sphere') {
    geometry = new THREE.SphereGeometry(Math.max(part.radius, 1e-6), 48, 32);
    geometry.applyMatrix4(Y_TO_Z);
    geometry.translate(0, 0, part.z);
  } else if (part.kind === 'lathe') {
    const points = part.profile.map(([r, z]) => new THREE.Vector2(inside * r, z));
    geometry = new THREE.LatheGeometry(points, 64);
    geometry.applyMatrix4(Y_TO_Z);
  } else if (part.kind === 'ellipsoid') {
    geometry = new THREE.SphereGeometry(1, 48, 32);
    geometry.applyMatrix4(Y_TO_Z);
    geometry.scale(...part.radii);
    geometry.translate(...part.center);
  } else if (part.kind === 'rod') {
    const a = new THREE.Vector3(...part.start);
    const b = new THREE.Vector3(...part.end);
    const length = Math.max(a.distanceTo(b), 1e-9);
    geometry = new THREE.CylinderGeometry(part.radius, part.radius, length, 16);
    const turn = new THREE.Quaternion().setFromUnitVectors(
      new THREE.Vector3(0, 1, 0), b.clone().sub(a).normalize());
    geometry.applyQuaternion(turn);
    geometry.translate(...a.clone().add(b).multiplyScalar(0.5).toArray());
  } else {
    throw new Error(`kreisel explore cannot draw a part of kind ${part.kind}`);
  }
  const m = new THREE.Mesh(geometry, materials[part.role] || materials.hull);
  m.name = part.name;
  return m;
}

function line(color, capacity) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * capacity), 3));
  geometry.setDrawRange(0, 0);
  return new THREE.Line(geometry, new THREE.LineBasicMaterial({ color }));
}

export class View3D {
  constructor(element) {
    this.element = element;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    element.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0xe9edf2);
    this.camera = new THREE.PerspectiveCamera(40, 1, 1e-4, 100);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    // paused, the scene is drawn again only when the camera moves
    this.dirty = true;
    this.controls.addEventListener('change', () => { this.dirty = true; });
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8090a0, 2.0));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(1, -2, 3);
    this.scene.add(sun);
    this.materials = {
      contact: new THREE.MeshStandardMaterial({ map: stripes('#c0392b', '#f1c40f', 12), roughness: 0.5 }),
      hull: new THREE.MeshStandardMaterial({ map: stripes('#2e86c1', '#ecf0f1', 8), roughness: 0.5 }),
      pivot: new THREE.MeshStandardMaterial({ color: 0x444444 }),
    };
    this.body = new THREE.Group();
    this.scene.add(this.body);
    this.world = new THREE.Group();
    this.scene.add(this.world);
    // each touching part's contact point and the floor's normal and friction forces on it
    this.forces = new THREE.Group();
    this.scene.add(this.forces);
    this.arrows = [];
    this.showForces = true;
    this.run = null;
    this.showTraces = true;
    this.follow = true;
    new ResizeObserver(() => this.resize()).observe(element);
    this.resize();
  }

  resize() {
    const w = this.element.clientWidth || 600;
    const h = this.element.clientHeight || 400;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  // A new run: its body, floor and traces; the camera frames it.
  setRun(run) {
    this.run = run;
    this.body.clear();
    this.world.clear();
    // the hull of a body of spheroids and rings lies on its parts: drawn just inside them
    const lathes = run.body.parts.some((p) => p.role === 'contact' && p.kind === 'lathe');
    for (const part of run.body.parts) {
      this.body.add(mesh(part, this.materials, lathes && part.role === 'hull' ? HULL_INSIDE : 1));
    }
    const L = run.body.axis; // signed: a tippe top's is drawn toward its stem, at -e3
    // the scale of the scene: the body's own size (a disk's axis is short, its radius not)
    const R = Math.max(Math.abs(L), bodyReach(run.body.parts));
    const n = run.t.length;
    const play = run.body.origin === 'com';
    // the figure axis, drawn in the body
    const axis = new THREE.BufferGeometry().setFromPoints(
      [new THREE.Vector3(0, 0, 0), new THREE.Vector3(0, 0, L)]);
    this.body.add(new THREE.Line(axis, new THREE.LineBasicMaterial({ color: 0x222222 })));
    // the tip of the figure axis and the contact point, at every sample
    this.tips = new Float32Array(3 * n);
    const q = new THREE.Quaternion();
    const v = new THREE.Vector3();
    let reach = R;
    for (let i = 0; i < n; i++) {
      const [w, x, y, z] = run.quaternion[i];
      v.set(0, 0, L).applyQuaternion(q.set(x, y, z, w));
      if (play) v.add(new THREE.Vector3(...run.com[i]));
      this.tips.set([v.x, v.y, v.z], 3 * i);
      if (play) reach = Math.max(reach, Math.hypot(run.com[i][0], run.com[i][1]) + R);
    }
    this.tipLine = line(0x8e44ad, n);
    this.tipLine.geometry.attributes.position.array.set(this.tips);
    this.world.add(this.tipLine);
    const floorZ = play ? 0 : -1.15 * R;
    if (play) {
      this.contactLine = line(0xd35400, n);
      const a = this.contactLine.geometry.attributes.position.array;
      for (let i = 0; i < n; i++) a.set([run.contact_point[i][0], run.contact_point[i][1], 1e-3 * R], 3 * i);
      this.world.add(this.contactLine);
    } else {
      this.contactLine = null;
      const stand = new THREE.CylinderGeometry(0.03 * R, 0.08 * R, -floorZ, 24);
      stand.applyMatrix4(Y_TO_Z);
      stand.translate(0, 0, floorZ / 2);
      this.world.add(new THREE.Mesh(stand, this.materials.pivot));
    }
    this.setArrows(run, R);
    const size = 4 * reach;
    const grid = new THREE.GridHelper(size, 20, 0x8a96a3, 0xc3cad3);
    grid.rotation.x = Math.PI / 2;
    grid.position.z = floorZ;
    this.world.add(grid);
    const floor = new THREE.Mesh(new THREE.PlaneGeometry(size, size),
      // a little transparent: what goes below the floor (a pivot top's body, the stem side
      // of an inverted tippe top's axis) still shows
      new THREE.MeshStandardMaterial({ color: 0xdfe4ea, roughness: 0.9, transparent: true, opacity: 0.8 }));
    floor.position.z = floorZ - 1e-4 * R;
    this.world.add(floor);
    // framed on the body as it starts: the sphere of radius R about its origin (a play top's
    // centre of mass, h above the floor) fills about 3/4 of the view's height
    const h = play ? run.com[0][2] : 0;
    const target = new THREE.Vector3(run.com ? run.com[0][0] : 0, run.com ? run.com[0][1] : 0,
      play ? 0.5 * h : 0);
    const distance = (1.3 * Math.max(R, 0.5 * h + R)) / Math.tan(((this.camera.fov / 2) * Math.PI) / 180);
    this.camera.near = distance / 500;
    this.camera.far = 500 * distance;
    this.camera.updateProjectionMatrix();
    // low over the floor (12 degrees): a top standing on its peg shows the peg under its ball
    this.home = { target, distance, elevation: (12 * Math.PI) / 180, azimuth: -0.92 };
    this.resetCamera();
    this.setTime(0, 0);
  }

  // One contact point and two arrows per contact part (play tops): the normal force, up,
  // and the friction force, along the floor, both `scale` m per N: the weight m g is drawn
  // 1.5 body sizes long.
  setArrows(run, R) {
    this.forces.clear();
    this.arrows = [];
    const c = run.contacts;
    if (!c) return;
    this.forceScale = (1.5 * R) / c.weight;
    this.arrowR = R;
    const up = new THREE.Vector3(0, 0, 1);
    const o = new THREE.Vector3();
    c.parts.forEach((name) => {
      const point = new THREE.Mesh(new THREE.SphereGeometry(0.05 * R, 16, 12),
        new THREE.MeshBasicMaterial({ color: ARROW_COLOURS.point }));
      const normal = new THREE.ArrowHelper(up, o, R, ARROW_COLOURS.normal, 0.25 * R, 0.12 * R);
      const friction = new THREE.ArrowHelper(up, o, R, ARROW_COLOURS.friction, 0.25 * R, 0.12 * R);
      for (const [what, obj] of [['point', point], ['normal', normal], ['friction', friction]]) {
        // drawn over the body: the contact lies under it, the normal force points into it
        obj.traverse((m) => {
          if (m.material) m.material.depthTest = false;
          m.renderOrder = 10;
        });
        obj.name = `${name} ${what}`;
        obj.userData = { part: name, what, force: 0 };
        this.forces.add(obj);
      }
      this.arrows.push({ part: name, point, normal, friction });
    });
  }

  // The contact arrows at sample k: shown for the parts touching (not in flight).
  poseArrows(k) {
    const c = this.run && this.run.contacts;
    if (!c) return;
    const flight = c.states.indexOf('flight');
    const R = this.arrowR; // the body size the arrows were made for
    this.arrows.forEach((a, p) => {
      const on = this.showForces && c.state[p][k] !== flight;
      a.point.visible = on;
      a.normal.visible = on;
      a.friction.visible = on;
      if (!on) return;
      const [x, y, z] = c.point[p][k];
      const at = new THREE.Vector3(x, y, z + 1e-3 * R);
      a.point.position.copy(at);
      const n = c.normal[p][k] || 0;
      a.normal.position.copy(at);
      a.normal.setDirection(new THREE.Vector3(0, 0, 1));
      a.normal.setLength(Math.max(n * this.forceScale, 1e-6 * R), 0.25 * R, 0.12 * R);
      a.normal.userData.force = n;
      const [fx, fy] = c.friction[p][k].map((v) => v || 0);
      const f = Math.hypot(fx, fy);
      a.friction.position.copy(at);
      a.friction.visible = f > 0;
      if (f > 0) {
        a.friction.setDirection(new THREE.Vector3(fx / f, fy / f, 0));
        a.friction.setLength(f * this.forceScale, Math.min(0.25 * R, 0.5 * f * this.forceScale),
          Math.min(0.12 * R, 0.25 * f * this.forceScale));
      }
      a.friction.userData.force = f;
      a.friction.userData.direction = f > 0 ? [fx / f, fy / f] : [0, 0];
    });
    this.arrowSample = k;
  }

  // The camera at `distance` from the target, seen from `elevation` above the floor and
  // `azimuth` about the vertical (rad).
  look(elevation, azimuth, distance = this.home.distance, target = this.controls.target) {
    const c = Math.cos(elevation);
    this.controls.target.copy(target);
    this.camera.position.set(target.x + distance * c * Math.cos(azimuth),
      target.y + distance * c * Math.sin(azimuth), target.z + distance * Math.sin(elevation));
    this.controls.update();
    this.dirty = true;
  }

  // The camera as the run started, over the body where it is now when it follows it.
  resetCamera() {
    if (!this.home) return;
    const t = this.home.target.clone();
    if (this.follow && this.run && this.run.com) t.setX(this.body.position.x).setY(this.body.position.y);
    this.look(this.home.elevation, this.home.azimuth, this.home.distance, t);
  }

  // Level with the target, looking along +y; straight down on the floor.
  sideView() { this.look(0, -Math.PI / 2, this.camera.position.distanceTo(this.controls.target)); }

  topView() { this.look(Math.PI / 2 - 1e-4, -Math.PI / 2, this.camera.position.distanceTo(this.controls.target)); }

  // Poses the body between samples i and i + 1 (frac in [0, 1)) and draws the traces so far.
  setTime(i, frac) {
    const run = this.run;
    if (!run) return;
    const n = run.t.length;
    const j = Math.min(i + 1, n - 1);
    const [w0, x0, y0, z0] = run.quaternion[i];
    const [w1, x1, y1, z1] = run.quaternion[j];
    const q0 = new THREE.Quaternion(x0, y0, z0, w0);
    this.body.quaternion.copy(q0.slerp(new THREE.Quaternion(x1, y1, z1, w1), frac));
    if (run.com) {
      const a = new THREE.Vector3(...run.com[i]);
      this.body.position.copy(a.lerp(new THREE.Vector3(...run.com[j]), frac));
    } else {
      this.body.position.set(0, 0, 0);
    }
    if (this.follow) {
      // the camera rides along with the body over the floor (the user still turns it)
      const dx = this.body.position.x - this.controls.target.x;
      const dy = this.body.position.y - this.controls.target.y;
      this.controls.target.x += dx;
      this.controls.target.y += dy;
      this.camera.position.x += dx;
      this.camera.position.y += dy;
    }
    this.poseArrows(frac < 0.5 ? i : j);
    const shown = this.showTraces ? i + 1 : 0;
    this.tipLine.geometry.setDrawRange(0, shown);
    if (this.contactLine) this.contactLine.geometry.setDrawRange(0, shown);
  }

  render() {
    this.controls.update();
    this.renderer.render(this.scene, this.camera);
    this.dirty = false;
  }
}
