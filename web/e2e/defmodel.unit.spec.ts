// Unit tests of the definition editor's model (src/defmodel.ts), in Node
// without a page or a server: the `.rig.json` form read and written back,
// <geo> files moved to the folder a definition is saved in, the links
// refused, and what hangs from the Rig node being all that is written.

import { expect, test } from '@playwright/test';
import type { ComponentSchema, RigJson } from '../src/api';
import { DefinitionModel, kRig, uuid4 } from '../src/defmodel';

function schema(type: string, over: Partial<ComponentSchema> = {}): ComponentSchema {
  return {
    type, help: '', params: [], guides: { min: 1, max: -1, names: [], help: '' }, controls: [],
    hooks: ['guide[i]'], features: [], rootOnly: false, needsParent: false, ...over,
  };
}

function model(): DefinitionModel {
  const m = new DefinitionModel();
  m.schemas = new Map([
    ['global', schema('global', { rootOnly: true, guides: { min: 0, max: 0, names: [], help: '' } })],
    ['fkChain', schema('fkChain', { params: [{ name: 'count', type: 'int', default: 2 }] })],
    ['eye', schema('eye', { needsParent: true })],
  ]);
  return m;
}

const kDefinition: RigJson = {
  rig: {
    name: 'hero',
    version: '1.2',
    guiLocation: [16, 110],
    geometry: [{ file: '../chars/hero.glb' }, { file: 'extra.glb', name: 'body' }],
    features: { stretch: true },
    components: [
      {
        type: 'global', name: 'root', side: 'C', version: '1.0', rigId: 'r-global', guiLocation: [190, 20],
        children: [
          {
            type: 'fkChain', name: 'arm', side: 'L', version: '1.1', rigId: 'r-arm', attach: 'START', guiLocation: [362, 90],
            guides: [{ name: 'a', joint: 'upper_arm.L', rotate: [0, 0, 0, 1] }, { joint: 'forearm.L', translate: [0, 0.1, 0] }],
            controls: [{ role: 'fk', size: 0.2, shape: 'circle' }],
            params: { count: 3 },
            extraKey: 'kept',
          },
        ],
      },
    ],
  },
};

test('a definition read and written back is the same definition', () => {
  const m = model();
  m.load(kDefinition, '/root/rigs');
  expect(m.nodes.size).toBe(3);
  // <geo> files are absolute in the model...
  expect(m.rig.geometry.map((g) => g.file)).toEqual(['/root/chars/hero.glb', '/root/rigs/extra.glb']);
  // ...and relative to the folder of the file written.
  expect(m.toJson('/root/rigs')).toEqual(kDefinition);
  const elsewhere = m.toJson('/root/rigs/sub');
  expect(elsewhere.rig.geometry).toEqual([{ file: '../../chars/hero.glb' }, { file: '../extra.glb', name: 'body' }]);
  expect(m.toJson(null).rig.geometry![0]!.file).toBe('/root/chars/hero.glb');
});

test('components without a place are laid out as a tree, and get a rigId', () => {
  const m = model();
  m.load({ rig: { components: [{ type: 'global', children: [{ type: 'fkChain' }] }] } }, '');
  const global = m.nodes.get(m.idOf('global')!)!;
  const chain = m.nodes.get(m.idOf('fkChain')!)!;
  expect([global.x, global.y]).toEqual([190, 20]);
  expect([chain.x, chain.y]).toEqual([362, 90]);
  expect(chain.parent).toBe(global.id);
  expect(chain.rigId).toMatch(/^[0-9a-f]{8}-[0-9a-f]{4}-4[0-9a-f]{3}-[89ab][0-9a-f]{3}-[0-9a-f]{12}$/);
  expect(uuid4()).not.toBe(uuid4());
});

test('links: root-only, needs a parent, its own parent and cycles are refused', () => {
  const m = model();
  const global = m.addComponent('global')!;
  const a = m.addComponent('fkChain')!;
  const b = m.addComponent('fkChain')!;
  const eye = m.addComponent('eye')!;
  expect(m.addComponent('noSuchType')).toBeNull();
  expect([global.name, a.name, b.name]).toEqual(['global', 'fkChain', 'fkChain2']);
  expect(m.linkProblem(a.id, global.id)).toContain('root-only');
  expect(m.linkProblem(kRig, eye.id)).toContain('needs a parent');
  expect(m.linkProblem(a.id, a.id)).toContain('its own parent');
  expect(m.linkProblem(a.id, kRig)).toContain('the Rig node cannot have a parent');
  expect(m.connect(a.id, b.id)).toBeNull();
  expect(m.linkProblem(b.id, a.id)).toBe('cycle: fkChain → fkChain2 → fkChain');
  expect(m.connect(b.id, a.id)).not.toBeNull();
  expect(a.parent).toBeNull();
});

test('only what hangs from the Rig node is written; a removed node lets its children go', () => {
  const m = model();
  const global = m.addComponent('global')!;
  const chain = m.addComponent('fkChain')!;
  const loose = m.addComponent('fkChain')!;
  m.connect(kRig, global.id);
  m.connect(global.id, chain.id);
  expect(m.attached(chain.id)).toBe(true);
  expect(m.attached(loose.id)).toBe(false);
  const written = m.toJson(null).rig.components!;
  expect(written.map((c) => c.name)).toEqual(['global']);
  expect(written[0]!.children!.map((c) => c.name)).toEqual(['fkChain']);
  // Removing the global (part of the definition) leaves the chain loose.
  expect(m.removeNode(global.id)).toBe(true);
  expect(chain.parent).toBeNull();
  expect(m.toJson(null).rig.components).toEqual([]);
  expect(m.removeNode(loose.id)).toBe(false);
  expect(m.removeNode(kRig)).toBe(false);
  expect(m.detach(chain.id)).toBe(false);
});

test("a parameter set to its default is not written; the scene's character is a new definition's geometry", () => {
  const m = model();
  const chain = m.addComponent('fkChain')!;
  const count = m.schemas.get('fkChain')!.params[0]!;
  DefinitionModel.setParam(chain, count, 4);
  expect(chain.params).toEqual({ count: 4 });
  DefinitionModel.setParam(chain, count, 2);
  expect(chain.params).toEqual({});
  expect(m.defaultGeometry('/root/hero.glb')).toBe(true);
  expect(m.defaultGeometry('/root/other.glb')).toBe(false);
  expect(m.rig.geometry).toEqual([{ file: '/root/hero.glb', name: '' }]);
  m.reset();
  m.geometrySet = true;
  expect(m.defaultGeometry('/root/hero.glb')).toBe(false);
});
