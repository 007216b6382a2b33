// What the replay viewer (viewer.js) uses of three.js, bundled by scripts/dashboard-assets
// into vendor/three.iife.min.js as the global THREE (only these, so the page stays small).
export {
  BoxGeometry, BufferAttribute, BufferGeometry, CanvasTexture, Color, CylinderGeometry,
  DirectionalLight, Float32BufferAttribute, Group, HemisphereLight, LineBasicMaterial,
  LineSegments, Mesh, MeshStandardMaterial, PerspectiveCamera, Quaternion, Scene,
  SphereGeometry, Sprite, SpriteMaterial, Vector3, WebGLRenderer,
} from "three";
export { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
