#!/usr/bin/env python3
# Makes fuzz/regressions/load_vgeo/non_minimal_cluster_code.vgeo from a valid .vgeo (format v9): widens
# one position field of the first cluster whose vertex stream keeps its word count, re-packs its
# vertices, and fixes the page and head checksums. Usage: widen_cluster_code.py IN.vgeo OUT.vgeo
# (the regression was made from fuzz/corpus/load_vgeo/tetra_and_triangle.vgeo).
import struct,sys
src,dst=sys.argv[1:3]
d=bytearray(open(src,'rb').read())
def fnv(b):
    h=0xcbf29ce484222325
    for x in b: h^=x; h=(h*0x100000001b3)&0xffffffffffffffff
    return h
nsec=struct.unpack_from('<I',d,12)[0]
secs={}
for i in range(nsec):
    sid,res,off,ln=struct.unpack_from('<IIQQ',d,32+24*i); secs[sid]=(off,ln)
import json
meta=json.loads(bytes(d[secs[1][0]:secs[1][0]+secs[1][1]]))
has_uvs=meta['has_uvs']; has_mats=len(meta['materials'])>1
pt=secs[11][0]; npages=secs[11][1]//64
nc=secs[4][1]//96
hw=8+2+(1 if has_uvs else 0)+(1 if has_mats else 0)
def getbits(words,bit,n):
    v=0
    for k in range(n):
        b=bit+k; v|=((words[b>>5]>>(b&31))&1)<<k
    return v
for c in range(nc):
    v=struct.unpack_from('<24I',d,secs[4][0]+96*c)
    data_off=v[17]; counts=v[19]; page=v[23]; vc=counts&0xff
    poff=struct.unpack_from('<Q',d,pt+64*page+32)[0]
    at=poff+4*data_off
    w=struct.unpack_from('<I',d,at+4*8)[0]
    # widths x, y, z, normal x, uv (per component), material in the widths word; the normals' y
    # width in bits 25-29 of the smallest x coordinate (above the triangle code's header)
    xw=struct.unpack_from('<I',d,at)[0]
    g=[(w>>(5*k))&31 for k in range(6)]
    f=[g[0],g[1],g[2],g[3],(xw>>25)&31,g[4],g[5]]
    vb=f[0]+f[1]+f[2]+f[3]+f[4]+2*f[5]+f[6]
    ks=[k for k in range(3) if f[k]<20]
    if not ks or (vc*vb+31)//32 != (vc*(vb+1)+31)//32: continue
    K=ks[0]
    nw=(vc*vb+31)//32
    vs=at+4*hw
    words=list(struct.unpack_from('<%dI'%nw,d,vs))
    fields=[]
    for i in range(vc):
        bit=i*vb; vals=[]
        for width in [f[0],f[1],f[2],f[3],f[4],f[5],f[5],f[6]]:
            vals.append(getbits(words,bit,width)); bit+=width
        fields.append(vals)
    f2=list(f); f2[K]+=1
    acc=0; bit=0
    for vals in fields:
        for width,val in zip([f2[0],f2[1],f2[2],f2[3],f2[4],f2[5],f2[5],f2[6]],vals):
            acc|=val<<bit; bit+=width
    out=[(acc>>(32*k))&0xffffffff for k in range(nw)]
    struct.pack_into('<%dI'%nw,d,vs,*out)
    struct.pack_into('<I',d,at+4*8,w+(1<<(5*K)))
    plen=struct.unpack_from('<Q',d,pt+64*page+40)[0]
    struct.pack_into('<Q',d,pt+64*page+48,fnv(d[poff:poff+plen]))
    head_end=secs[12][0]
    struct.pack_into('<Q',d,16,0)
    struct.pack_into('<Q',d,16,fnv(d[:head_end]))
    open(dst,'wb').write(d); print('widened cluster',c,'page',page); break
