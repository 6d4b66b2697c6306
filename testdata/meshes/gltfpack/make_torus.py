import json, math, struct, base64
R, r, M, N = 2.0, 0.5, 32, 16
pos=[];nrm=[];uv=[]
for i in range(M+1):
    u=2*math.pi*i/M
    for j in range(N+1):
        v=2*math.pi*j/N
        cx,cy=math.cos(u),math.sin(u)
        nx,ny,nz=cx*math.cos(v),cy*math.cos(v),math.sin(v)
        pos.append(((R+r*math.cos(v))*cx+10.0,(R+r*math.cos(v))*cy-3.0,r*math.sin(v)+1.0))
        nrm.append((nx,ny,nz)); uv.append((i/M,j/N))
idx=[]
for i in range(M):
    for j in range(N):
        a=i*(N+1)+j; b=(i+1)*(N+1)+j
        idx += [a,b,a+1, a+1,b,b+1]
binp=b''.join(struct.pack('<3f',*p) for p in pos)
binn=b''.join(struct.pack('<3f',*p) for p in nrm)
binu=b''.join(struct.pack('<2f',*p) for p in uv)
bini=b''.join(struct.pack('<I',i) for i in idx)
data=binp+binn+binu+bini
mn=[min(p[k] for p in pos) for k in range(3)]; mx=[max(p[k] for p in pos) for k in range(3)]
n=len(pos)
g={"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
 "nodes":[{"mesh":0,"translation":[0,0,5]}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2},"indices":3,"material":0}]}],
 "materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.8,0.3,0.2,1]}}],
 "buffers":[{"byteLength":len(data),"uri":"torus.bin"}],
 "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":len(binp)},{"buffer":0,"byteOffset":len(binp),"byteLength":len(binn)},
   {"buffer":0,"byteOffset":len(binp)+len(binn),"byteLength":len(binu)},{"buffer":0,"byteOffset":len(binp)+len(binn)+len(binu),"byteLength":len(bini)}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":n,"type":"VEC3","min":mn,"max":mx},
   {"bufferView":1,"componentType":5126,"count":n,"type":"VEC3"},
   {"bufferView":2,"componentType":5126,"count":n,"type":"VEC2"},
   {"bufferView":3,"componentType":5125,"count":len(idx),"type":"SCALAR"}]}
open('torus.gltf','w').write(json.dumps(g)); open('torus.bin','wb').write(data)
print(n, len(idx)//3)
