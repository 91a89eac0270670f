// The `svetlo` object of the page (docs/web.md, the contract's "In the browser"):
//   await svetlo.ready;
//   const {width, height, seconds, pixels} = await svetlo.render(SCENE, {engine, width,
//       height, spp, seed, threads, set});
// SCENE is a bundled scene's name ("cornell.json"), a visitor's file put there by
// svetlo.addFiles ("visitor/model.glb"), or a scene object; pixels is a Float32Array of linear
// RGB, top row first. A bad scene rejects with an Error whose message is the one-line error.
// Renders run one at a time in a worker (render_worker.js), in order. An `onPass(pass)` option
// is called with each pass of a progressive engine ({passes, seconds, width, height, pixels});
// svetlo.cancel() ends the render in progress after its pass (a cross-origin isolated page:
// svetlo.canCancel), which then resolves with the passes done and `cancelled` true.
(function () {
    'use strict';
    const worker = new Worker(new URL('render_worker.js', document.currentScript.src));
    const waiting = new Map();  // id -> {resolve, reject}
    let nextId = 1;
    let info = {scenes: [], engines: [], cores: 1, memory: null, cancelAt: 0};
    let readyResolve, readyReject;
    const ready = new Promise((resolve, reject) => {
        readyResolve = resolve;
        readyReject = reject;
    });
    worker.onmessage = (event) => {
        const data = event.data;
        if (data.ready) {
            info = data;
            readyResolve();
            return;
        }
        if (data.failed !== undefined) {
            readyReject(new Error('svetlo: the WebAssembly module did not start: ' + data.failed));
            return;
        }
        const call = waiting.get(data.id);
        if (!call) return;
        if (data.pass !== undefined) {  // a pass of the render in progress
            if (call.onPass) call.onPass(data.pass);
            return;
        }
        waiting.delete(data.id);
        if (data.error !== undefined) call.reject(new Error(data.error));
        else if (data.names !== undefined) call.resolve(data.names);
        else call.resolve({width: data.width, height: data.height, seconds: data.seconds,
                           passes: data.passes, cancelled: data.cancelled, pixels: data.pixels});
    };
    // The worker failed: the start, and every render waiting, end with its message.
    worker.onerror = (event) => {
        const error = new Error('svetlo: ' + event.message);
        readyReject(error);
        for (const call of waiting.values()) call.reject(error);
        waiting.clear();
    };

    /// Threads above one need a cross-origin isolated page (COOP and COEP headers).
    function threadsFor(asked) {
        if (!self.crossOriginIsolated) return 1;
        return asked === undefined || asked === null ? 0 : asked;
    }

    function render(scene, options) {
        return ready.then(() => new Promise((resolve, reject) => {
            const id = nextId++;
            const opts = Object.assign({}, options || {});
            const onPass = typeof opts.onPass === 'function' ? opts.onPass : null;
            delete opts.onPass;  // (a function does not cross to the worker)
            waiting.set(id, {resolve, reject, onPass});
            opts.threads = threadsFor(opts.threads);
            const isText = typeof scene !== 'string';
            worker.postMessage({id, scene: isText ? JSON.stringify(scene) : scene, isText,
                                options: opts, wantsPasses: onPass !== null});
        }));
    }

    /// The visitor's own files (File objects, or {name, bytes} with bytes an ArrayBuffer or a
    /// typed array), put under visitor/ beside the bundled scenes, each under its own name
    /// without folders: a scene or a model and the files it names (an OBJ's MTL and textures,
    /// a glTF's buffers). Resolves to the names given; svetlo.render('visitor/NAME') renders.
    function addFiles(files) {
        return ready.then(() => Promise.all(Array.from(files, async (f) => {
            const bytes = f instanceof Blob ? await f.arrayBuffer() : f.bytes;
            const copy = bytes instanceof ArrayBuffer ? bytes.slice(0)
                : bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
            return {name: String(f.name), bytes: copy};
        }))).then((list) => new Promise((resolve, reject) => {
            const id = nextId++;
            waiting.set(id, {resolve, reject});
            worker.postMessage({id, files: list}, list.map((f) => f.bytes));
        }));
    }

    /// Ends the render in progress after its pass; false where the page cannot (its module
    /// has no memory shared with the page: not cross-origin isolated).
    function cancel() {
        if (!info.memory) return false;
        Atomics.store(new Int8Array(info.memory), info.cancelAt, 1);
        return true;
    }

    self.svetlo = {
        ready,
        render,
        addFiles,
        cancel,
        get canCancel() { return info.memory !== null; },
        get scenes() { return info.scenes.slice(); },
        get engines() { return info.engines.map((e) => e.name); },
        get threads() { return self.crossOriginIsolated ? info.cores : 1; },
    };
})();
