// Reads the scene's binary glTF (GET /api/character.glb) into the objects
// the viewport draws: the store holds the result (store.ts's Character),
// as three.js's editor holds its scene for its viewport to draw.

import type * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import type { NodesAnswer } from './api';
import type { Character } from './store';

export async function parseCharacter(glb: ArrayBuffer, nodes: NodesAnswer): Promise<Character> {
  const gltf = await new GLTFLoader().parseAsync(glb, '');
  const fileMaterials = new Set<THREE.Material>();
  gltf.scene.traverse((o) => {
    const mesh = o as THREE.Mesh;
    if (!mesh.isMesh) return;
    for (const m of Array.isArray(mesh.material) ? mesh.material : [mesh.material]) {
      if (gltf.parser.associations.get(m)?.materials !== undefined) fileMaterials.add(m);
    }
  });
  return { root: gltf.scene, fileMaterials, nodes };
}
