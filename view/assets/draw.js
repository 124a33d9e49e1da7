// Scene objects: what sinew evaluated, drawn. Joints as Maya draws them (a sphere and a
// wire pyramid to each child joint), transforms as locator crosses, markers as small
// diamonds, meshes and curves from the positions sinew computed. The browser computes
// nothing but normals for shading.
import * as THREE from 'three';

const JOINT_COLOR = 0x5aa0ff, BONE_COLOR = 0x7fb4ff, XFORM_COLOR = 0xf0c040, MARKER_COLOR = 0x40e0a0;
const SELECT_COLOR = 0xffffff, ERROR_COLOR = 0xff3030;

export class Drawing {
  constructor(root) {
    this.root = root;
    this.group = new THREE.Group();
    root.add(this.group);
    this.items = [];
    this.meshes = [];
    this.curves = [];
    this.pickables = [];
    this.size = 0.05;
  }

  dispose() {
    this.group.traverse((o) => { o.geometry?.dispose(); o.material?.dispose?.(); });
    this.root.remove(this.group);
  }

  /// Builds the objects of `scene` (from /api/scene); `frame` is a first frame's buffer
  /// used to size joints from bone lengths.
  build(scene, buffer) {
    const mats = new Float64Array(buffer, 0, scene.items.length * 16);
    const pos = (i) => new THREE.Vector3(mats[i * 16 + 12], mats[i * 16 + 13], mats[i * 16 + 14]);
    const lengths = [];
    scene.items.forEach((it, i) => { if (it.parent !== null) lengths.push(pos(i).distanceTo(pos(it.parent))); });
    lengths.sort((a, b) => a - b);
    const median = lengths.filter((l) => l > 1e-9)[Math.floor(lengths.length / 2)] || 1;
    this.size = median * 0.12;
    const sphere = new THREE.SphereGeometry(1, 12, 8);
    const pickGeo = new THREE.SphereGeometry(1.6, 8, 6);
    const pickMat = new THREE.MeshBasicMaterial({ visible: false });
    for (const [i, it] of scene.items.entries()) {
      const o = { item: it, index: i, node: new THREE.Group(), bones: [] };
      o.node.matrixAutoUpdate = false;
      let color = XFORM_COLOR;
      if (it.kind === 'joint') {
        color = JOINT_COLOR;
        const s = new THREE.LineSegments(new THREE.WireframeGeometry(sphere), new THREE.LineBasicMaterial({ color }));
        s.scale.setScalar(this.size * 0.5 * Math.min(it.radius, 4));
        o.shape = s;
      } else if (it.kind === 'marker') {
        color = MARKER_COLOR;
        const g = new THREE.OctahedronGeometry(this.size * 0.6);
        o.shape = new THREE.LineSegments(new THREE.WireframeGeometry(g), new THREE.LineBasicMaterial({ color }));
      } else {
        const s = this.size * 2;
        const g = new THREE.BufferGeometry().setFromPoints([
          new THREE.Vector3(-s, 0, 0), new THREE.Vector3(s, 0, 0), new THREE.Vector3(0, -s, 0),
          new THREE.Vector3(0, s, 0), new THREE.Vector3(0, 0, -s), new THREE.Vector3(0, 0, s)]);
        o.shape = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color }));
      }
      o.color = color;
      o.node.add(o.shape);
      const pick = new THREE.Mesh(pickGeo, pickMat);
      pick.scale.setScalar(this.size * (it.kind === 'transform' ? 1.5 : 0.5));
      pick.userData.name = it.name;
      o.node.add(pick);
      this.pickables.push(pick);
      this.group.add(o.node);
      this.items.push(o);
    }
    // Bones: a four-sided wire pyramid from each joint to each joint child, along +Y.
    const pyramid = new THREE.ConeGeometry(1, 1, 4, 1, false);
    pyramid.translate(0, 0.5, 0);
    const boneGeo = new THREE.WireframeGeometry(pyramid);
    for (const o of this.items) {
      const p = o.item.parent;
      if (o.item.kind !== 'joint' || p === null || this.items[p].item.kind !== 'joint') continue;
      const bone = new THREE.LineSegments(boneGeo, new THREE.LineBasicMaterial({ color: BONE_COLOR }));
      bone.matrixAutoUpdate = false;
      bone.userData = { from: p, to: o.index };
      this.items[p].bones.push(bone);
      this.group.add(bone);
    }
    for (const m of scene.meshes) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(m.vertices * 3), 3));
      g.setIndex(m.triangles);
      const mat = new THREE.MeshLambertMaterial({ color: 0xb0b0b8, side: THREE.DoubleSide, transparent: true, opacity: 0.75 });
      const mesh = new THREE.Mesh(g, mat);
      mesh.frustumCulled = false;
      this.group.add(mesh);
      this.meshes.push({ info: m, mesh });
    }
    for (const c of scene.curves) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(c.samples * 3), 3));
      const line = new THREE.Line(g, new THREE.LineBasicMaterial({ color: 0x60d0ff }));
      line.frustumCulled = false;
      this.group.add(line);
      this.curves.push({ info: c, line });
    }
  }

  /// Applies one frame buffer (see view/src/scene.rs for its layout).
  update(buffer) {
    const n = this.items.length;
    const mats = new Float64Array(buffer, 0, n * 16);
    const m4 = new THREE.Matrix4();
    for (const o of this.items) {
      o.node.matrix.fromArray(mats, o.index * 16);
      o.node.matrixWorldNeedsUpdate = true;
    }
    const up = new THREE.Vector3(0, 1, 0), a = new THREE.Vector3(), b = new THREE.Vector3();
    const q = new THREE.Quaternion(), s = new THREE.Vector3();
    for (const o of this.items) {
      for (const bone of o.bones) {
        a.setFromMatrixPosition(this.items[bone.userData.from].node.matrix);
        b.setFromMatrixPosition(this.items[bone.userData.to].node.matrix);
        const d = b.clone().sub(a);
        const len = d.length();
        q.setFromUnitVectors(up, len > 1e-12 ? d.divideScalar(len) : up);
        const w = Math.min(this.size * 0.5 * Math.min(o.item.radius, 4), len * 0.25);
        s.set(w, len, w);
        bone.matrix.compose(a, q, s);
        bone.matrixWorldNeedsUpdate = true;
      }
    }
    for (const c of this.curves) {
      const src = new Float64Array(buffer, c.info.offset, c.info.samples * 3);
      c.line.geometry.attributes.position.array.set(src);
      c.line.geometry.attributes.position.needsUpdate = true;
    }
    for (const m of this.meshes) {
      const src = new Float32Array(buffer.slice(m.info.offset, m.info.offset + m.info.vertices * 12));
      m.mesh.geometry.attributes.position.array.set(src);
      m.mesh.geometry.attributes.position.needsUpdate = true;
      m.mesh.geometry.computeVertexNormals();
      m.mesh.geometry.computeBoundingSphere();
    }
    void m4;
  }

  /// Colours: the selection white, nodes with errors red.
  highlight(selected, errorNodes) {
    for (const o of this.items) {
      const c = o.item.name === selected ? SELECT_COLOR : errorNodes.has(o.item.name) ? ERROR_COLOR : o.color;
      o.shape.material.color.setHex(c);
      for (const b of o.bones) b.material.color.setHex(errorNodes.has(o.item.name) ? ERROR_COLOR : BONE_COLOR);
    }
  }

  /// World-space bounds of everything drawn.
  bounds() {
    const box = new THREE.Box3();
    const p = new THREE.Vector3();
    for (const o of this.items) box.expandByPoint(p.setFromMatrixPosition(o.node.matrix));
    for (const m of this.meshes) { m.mesh.geometry.computeBoundingBox(); box.union(m.mesh.geometry.boundingBox); }
    for (const c of this.curves) { c.line.geometry.computeBoundingBox(); box.union(c.line.geometry.boundingBox); }
    return box;
  }

  /// Screen position (pixels) of a drawn node, for tests and labels.
  screenPosition(name, camera, width, height) {
    const o = this.items.find((x) => x.item.name === name);
    if (!o) return null;
    const v = new THREE.Vector3().setFromMatrixPosition(o.node.matrix).project(camera);
    return { x: (v.x + 1) / 2 * width, y: (1 - v.y) / 2 * height };
  }
}
