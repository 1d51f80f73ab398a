// shlight's lighting in three.js: load a baked irradiance volume as a
// LightProbeGridWebGL, an SH environment light as a LightProbe, and a
// lightmapped glTF scene with its lightmaps on its materials.
//
// An ES module with no build step. It imports `three` and `three/addons/`
// through the page's import map (three.js r187 or a later r18x: the
// LightProbeGrid addons arrived in r187):
//
//   <script type="importmap">
//   { "imports": { "three": "./node_modules/three/build/three.module.js",
//                  "three/addons/": "./node_modules/three/examples/jsm/" } }
//   </script>
//
// The files are shlight's exports (docs/shvol.md, "three.js", and
// docs/exporters.md, "threejs"):
//   shlight volume SCENE --env ENV --format threejs -o grid.json
//   shlight convert VOLUME.shvol --format threejs -o grid.json
//   shlight project MAP --lmax 2 --format threejs -o probe.json
//   shlight lightmap SCENE.glb --env ENV -o lit.glb   (docs/lightmaps.md)
//
// Every failure (a missing file, a truncated or foreign document, numbers
// that do not fit the grid) rejects with a ShlightLoadError whose message
// names the file and the problem: a page shows it rather than a black scene.

import {
	ClampToEdgeWrapping,
	Data3DTexture,
	FloatType,
	HalfFloatType,
	LinearFilter,
	ObjectLoader,
	RGBAFormat,
	ShaderChunk,
	Vector3
} from 'three';
import { LightProbeGridWebGL } from 'three/addons/lighting/LightProbeGridWebGL.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { KTX2Loader } from 'three/addons/loaders/KTX2Loader.js';

/** The `metadata.type` of shlight's three.js grid document. */
export const GRID_DOCUMENT_TYPE = 'shlight.LightProbeGrid';
/** The newest document version this module reads. */
export const GRID_DOCUMENT_VERSION = 1;

/** Why a shlight export could not be loaded; the message names the file. */
export class ShlightLoadError extends Error {

	constructor( message ) {

		super( message );
		this.name = 'ShlightLoadError';

	}

}

/**
 * Fetches `url` and parses it as JSON.
 *
 * @param {string} url
 * @return {Promise<Object>}
 */
async function fetchJSON( url ) {

	let response;
	try {

		response = await fetch( url );

	} catch ( e ) {

		throw new ShlightLoadError( `${url}: cannot fetch (${e.message})` );

	}

	if ( ! response.ok ) {

		throw new ShlightLoadError( `${url}: cannot fetch (HTTP ${response.status} ${response.statusText})` );

	}

	return parseJSON( await response.text(), url );

}

/**
 * Parses `text` as JSON, naming `name` in the error.
 *
 * @param {string} text
 * @param {string} name
 * @return {Object}
 */
export function parseJSON( text, name ) {

	try {

		return JSON.parse( text );

	} catch ( e ) {

		throw new ShlightLoadError( `${name}: not a JSON document (${e.message}); is the file truncated?` );

	}

}

/**
 * Decodes standard base64 into bytes.
 *
 * @param {string} text
 * @return {Uint8Array}
 */
function decodeBase64( text ) {

	if ( typeof Uint8Array.fromBase64 === 'function' ) return Uint8Array.fromBase64( text );
	const binary = atob( text );
	const bytes = new Uint8Array( binary.length );
	for ( let i = 0; i < binary.length; i ++ ) bytes[ i ] = binary.charCodeAt( i );
	return bytes;

}

function isCount( v ) {

	return Number.isInteger( v ) && v > 0;

}

function isPoint( v ) {

	return Array.isArray( v ) && v.length === 3 && v.every( Number.isFinite );

}

/**
 * A LightProbeGridWebGL from shlight's grid document `doc` (already parsed):
 * its box on the volume's bounds, its resolution the volume's, its atlas the
 * document's texture. Ready to `scene.add`. If you move the grid, call its
 * `updateBoundingBox()`.
 *
 * @param {Object} doc - the parsed `--format threejs` volume export.
 * @param {string} [name] - how errors name the document.
 * @return {LightProbeGridWebGL}
 */
export function lightProbeGridFromJSON( doc, name = 'light probe grid' ) {

	const fail = ( problem ) => {

		throw new ShlightLoadError( `${name}: ${problem}` );

	};

	if ( doc === null || typeof doc !== 'object' || doc.metadata?.type !== GRID_DOCUMENT_TYPE ) {

		if ( doc?.object?.type === 'LightProbe' ) fail( 'is a LightProbe (load it with loadLightProbe), not a volume' );
		fail( `not a shlight three.js volume export (metadata.type is not "${GRID_DOCUMENT_TYPE}")` );

	}

	if ( ! ( doc.metadata.version <= GRID_DOCUMENT_VERSION ) ) {

		fail( `document version ${doc.metadata.version} is newer than this loader reads (${GRID_DOCUMENT_VERSION})` );

	}

	const res = doc.resolution;
	if ( ! Array.isArray( res ) || res.length !== 3 || ! res.every( isCount ) ) fail( 'resolution is not three positive probe counts' );
	const [ nx, ny, nz ] = res;
	const box = doc.boundingBox;
	if ( ! isPoint( box?.min ) || ! isPoint( box?.max ) ) fail( 'boundingBox.min and boundingBox.max are not points' );
	const min = new Vector3().fromArray( box.min );
	const max = new Vector3().fromArray( box.max );
	if ( ! ( min.x < max.x && min.y < max.y && min.z < max.z ) ) fail( 'boundingBox is empty (min is not below max on every axis)' );

	const atlas = doc.atlas ?? {};
	const depth = 7 * ( nz + 2 );
	if ( atlas.width !== nx || atlas.height !== ny || atlas.depth !== depth ) {

		fail( `atlas is ${atlas.width}x${atlas.height}x${atlas.depth}, not ${nx}x${ny}x${depth} (7 sub-volumes of nz + 2 slices)` );

	}

	if ( atlas.format !== 'RGBAFormat' ) fail( `atlas.format is ${atlas.format}, not RGBAFormat` );
	const bytesPerNumber = { HalfFloatType: 2, FloatType: 4 }[ atlas.type ];
	if ( bytesPerNumber === undefined ) fail( `atlas.type is ${atlas.type}, not HalfFloatType or FloatType` );
	const byteLength = nx * ny * depth * 4 * bytesPerNumber;
	if ( atlas.byteLength !== byteLength ) fail( `atlas.byteLength is ${atlas.byteLength}, not the ${byteLength} its size needs` );
	if ( atlas.encoding !== 'base64' || typeof atlas.data !== 'string' ) fail( 'atlas.data is not base64 text' );

	let bytes;
	try {

		bytes = decodeBase64( atlas.data );

	} catch ( e ) {

		fail( `atlas.data is not base64 (${e.message})` );

	}

	if ( bytes.byteLength !== byteLength ) fail( `atlas.data holds ${bytes.byteLength} bytes, not ${byteLength}: the file is truncated or damaged` );

	const data = bytesPerNumber === 2 ? new Uint16Array( bytes.buffer, bytes.byteOffset, byteLength / 2 ) : new Float32Array( bytes.buffer, bytes.byteOffset, byteLength / 4 );
	if ( bytesPerNumber === 4 && ! data.every( Number.isFinite ) ) fail( 'atlas.data holds numbers that are not finite' );

	const texture = new Data3DTexture( data, nx, ny, depth );
	texture.format = RGBAFormat;
	texture.type = bytesPerNumber === 2 ? HalfFloatType : FloatType;
	texture.minFilter = LinearFilter;
	texture.magFilter = LinearFilter;
	texture.wrapS = texture.wrapT = texture.wrapR = ClampToEdgeWrapping;
	texture.generateMipmaps = false;
	texture.unpackAlignment = 1;
	texture.needsUpdate = true;

	const size = new Vector3().subVectors( max, min );
	const grid = new LightProbeGridWebGL( size.x, size.y, size.z, nx, ny, nz );
	grid.name = name;
	grid.position.addVectors( min, max ).multiplyScalar( 0.5 );
	grid.updateBoundingBox();
	// The box exactly as the file gives it (centre +- size / 2 can round).
	grid.boundingBox.min.copy( min );
	grid.boundingBox.max.copy( max );
	grid.texture = texture;
	grid.userData.shlight = { notes: doc.notes ?? [], lmax: doc.lmax, sourceLmax: doc.sourceLmax, precision: atlas.type };

	const dispose = grid.dispose.bind( grid );
	grid.dispose = () => {

		texture.dispose();
		dispose();

	};

	return grid;

}

/**
 * Loads shlight's `--format threejs` volume export at `url` as a
 * LightProbeGridWebGL, placed on the volume's box and filled with its
 * probes: `scene.add( await loadLightProbeGrid( 'grid.json' ) )`.
 *
 * @param {string} url
 * @return {Promise<LightProbeGridWebGL>}
 */
export async function loadLightProbeGrid( url ) {

	return lightProbeGridFromJSON( await fetchJSON( url ), url );

}

/**
 * A LightProbe from shlight's `--format threejs` coefficient export
 * (`LightProbe.toJSON()`), already parsed.
 *
 * @param {Object} doc
 * @param {string} [name] - how errors name the document.
 * @return {LightProbe}
 */
export function lightProbeFromJSON( doc, name = 'light probe' ) {

	const object = doc?.object;
	if ( object?.type !== 'LightProbe' ) {

		if ( doc?.metadata?.type === GRID_DOCUMENT_TYPE ) throw new ShlightLoadError( `${name}: is a volume (load it with loadLightProbeGrid), not a LightProbe` );
		throw new ShlightLoadError( `${name}: not a three.js LightProbe (object.type is not "LightProbe")` );

	}

	if ( ! Array.isArray( object.sh ) || object.sh.length !== 27 || ! object.sh.every( Number.isFinite ) ) {

		throw new ShlightLoadError( `${name}: object.sh is not 27 finite numbers (nine RGB coefficients)` );

	}

	const probe = new ObjectLoader().parse( doc );
	probe.name = probe.name || name;
	return probe;

}

/**
 * Loads shlight's `--format threejs` coefficient export at `url` as a
 * LightProbe: `scene.add( await loadLightProbe( 'probe.json' ) )`.
 *
 * @param {string} url
 * @return {Promise<LightProbe>}
 */
export async function loadLightProbe( url ) {

	return lightProbeFromJSON( await fetchJSON( url ), url );

}

/**
 * Either export, told apart by its content: a LightProbeGridWebGL for a
 * volume, a LightProbe for a coefficient export.
 *
 * @param {Object} doc
 * @param {string} [name]
 * @return {LightProbeGridWebGL|LightProbe}
 */
export function lightFromJSON( doc, name = 'light' ) {

	return doc?.metadata?.type === GRID_DOCUMENT_TYPE ? lightProbeGridFromJSON( doc, name ) : lightProbeFromJSON( doc, name );

}

/**
 * A GLTFLoader plugin for `MOZ_lightmap`: the material's `lightMap` is
 * the texture it names, read through its `texCoord` (shlight writes 1,
 * GLTFLoader's `uv1`), `lightMapIntensity` its `intensity` (shlight
 * writes what turns the texels into irradiance E, which three.js's
 * shader multiplies by `BRDF_Lambert = albedo / pi`).
 */
class MozLightmapPlugin {

	constructor( parser ) {

		this.parser = parser;
		this.name = 'MOZ_lightmap';

	}

	async extendMaterialParams( materialIndex, params ) {

		const ext = this.parser.json.materials[ materialIndex ]?.extensions?.MOZ_lightmap;
		if ( ! ext ) return;
		const map = await this.parser.getDependency( 'texture', ext.index );
		map.channel = ext.texCoord ?? 1;
		params.lightMap = map;
		params.lightMapIntensity = ext.intensity ?? 1;

	}

}

/**
 * Makes a material that holds the L0 page of an `sh-l1` lightmap as its
 * `lightMap` read the full L1 irradiance for its shading normal: `E(n) =
 * L0 + n.x L1x + n.y L1y + n.z L1z` per channel (shlight's layout for
 * three.js, world axes), times `lightMapIntensity`.
 *
 * @param {Material} material
 * @param {Texture[]} l1 - the `l1x`, `l1y`, `l1z` pages.
 */
function reconstructL1( material, l1 ) {

	for ( const t of l1 ) t.channel = material.lightMap.channel;
	material.onBeforeCompile = ( shader ) => {

		shader.uniforms.shlightL1x = { value: l1[ 0 ] };
		shader.uniforms.shlightL1y = { value: l1[ 1 ] };
		shader.uniforms.shlightL1z = { value: l1[ 2 ] };
		// three.js's own chunk, its lightmap line read as the L1 irradiance
		// for the shading normal in world axes (a view matrix's inverse on a
		// direction is its transpose).
		const chunk = ShaderChunk.lights_fragment_maps.replace(
			'vec3 lightMapIrradiance = lightMapTexel.rgb * lightMapIntensity;',
			/* glsl */`vec3 shlightN = normalize( ( vec4( normal, 0.0 ) * viewMatrix ).xyz );
		vec3 lightMapIrradiance = ( lightMapTexel.rgb
			+ shlightN.x * texture2D( shlightL1x, vLightMapUv ).rgb
			+ shlightN.y * texture2D( shlightL1y, vLightMapUv ).rgb
			+ shlightN.z * texture2D( shlightL1z, vLightMapUv ).rgb ) * lightMapIntensity;` );
		if ( chunk === ShaderChunk.lights_fragment_maps ) throw new ShlightLoadError( 'this three.js has no lightmap line to read L1 from (written for r187)' );
		shader.fragmentShader = shader.fragmentShader
			.replace( '#include <lights_fragment_maps>', chunk )
			.replace( 'void main() {', 'uniform sampler2D shlightL1x;\nuniform sampler2D shlightL1y;\nuniform sampler2D shlightL1z;\nvoid main() {' );

	};
	material.customProgramCacheKey = () => 'shlight-l1';
	material.needsUpdate = true;

}

/**
 * Loads a scene that `shlight lightmap --for threejs -o SCENE.glb` wrote,
 * with its lightmaps: each baked material gets its page as `lightMap`
 * (through `MOZ_lightmap`, linear, `uv1`); for the `sh-l1` basis each
 * also reconstructs the L1 irradiance for its shading normal, so normal
 * maps reshade it, always linearly (a `--non-linear` file's
 * reconstruction is not applied). The pages are half-float KTX2 images, read by a
 * KTX2Loader made ready for `renderer`. Resolves to GLTFLoader's result;
 * its `userData.shlightLightmap` is the file's `SHLIGHT_lightmap`
 * (docs/lightmaps.md).
 *
 * @param {string} url
 * @param {WebGLRenderer} renderer
 * @return {Promise<Object>}
 */
export async function loadLightmappedScene( url, renderer ) {

	const ktx2 = new KTX2Loader().detectSupport( renderer );
	const loader = new GLTFLoader().setKTX2Loader( ktx2 );
	loader.register( ( parser ) => new MozLightmapPlugin( parser ) );
	let gltf;
	try {

		gltf = await loader.loadAsync( url );

	} catch ( e ) {

		throw new ShlightLoadError( `${url}: ${e.message}` );

	} finally {

		ktx2.dispose();

	}

	const info = gltf.parser.json.extensions?.SHLIGHT_lightmap;
	if ( ! info ) throw new ShlightLoadError( `${url}: holds no SHLIGHT_lightmap: not a lightmap shlight wrote` );
	if ( info.engine !== 'threejs' ) throw new ShlightLoadError( `${url}: baked for ${info.engine} (units ${info.units}); three.js reads --for threejs` );
	gltf.userData.shlightLightmap = info;
	if ( info.basis === 'sh-l1' ) {

		// The pages after the first, by name, in the layers' order.
		const images = gltf.parser.json.images ?? [];
		const textures = gltf.parser.json.textures ?? [];
		const l1 = [];
		for ( const name of info.images.slice( 1 ) ) {

			const image = images.findIndex( ( i ) => i.name === name );
			const texture = textures.findIndex( ( t ) => ( t.extensions?.KHR_texture_basisu?.source ?? t.source ) === image );
			if ( texture < 0 ) throw new ShlightLoadError( `${url}: its page ${name} has no texture` );
			l1.push( await gltf.parser.getDependency( 'texture', texture ) );

		}

		gltf.scene.traverse( ( object ) => {

			const materials = Array.isArray( object.material ) ? object.material : object.material ? [ object.material ] : [];
			for ( const m of materials ) if ( m.lightMap && ! m.userData.shlightL1 ) {

				m.userData.shlightL1 = true;
				reconstructL1( m, l1 );

			}

		} );

	} else if ( info.basis !== 'irradiance' ) {

		throw new ShlightLoadError( `${url}: its basis ${info.basis} has no three.js reading` );

	}

	return gltf;

}
